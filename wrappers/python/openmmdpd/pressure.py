"""The DPD pressure tensor (docs/theory/pressure-tensor.md) from a DPD integrator, as numbers and as an
OpenMM reporter.

Every DPD integrator (`DPDThermostatIntegrator`) accumulates, once enabled with
`setPressureTensorEnabled(True)`, the pressure tensor

    P_ab = (1/V) [ sum_i m_i u_i,a u_i,b + sum_{i<j} r_ij,a F_ij,b ]   (positive = compressive)

sampled at the end of every step (u: peculiar velocities under shear), and returns its average
since the last `resetPressureTensor()`.  Six components in the order (xx, yy, zz, xy, xz, yz),
in kJ/mol/nm^3, which is kT/rc^3 in the reduced units of the scenes (kT = 1 kJ/mol, rc = 1 nm).
Parts: total, kinetic, conservative, thermostat (dissipative + random).
"""
import numpy as np
from openmm import unit

__all__ = ["COMPONENTS", "PARTS", "PRESSURE_UNIT", "pressure_tensor", "check_integrator", "PressureTensorReporter"]

COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
PARTS = ("total", "kinetic", "conservative", "thermostat")  # DPDThermostatIntegrator.Pressure<Part> = 0..3
PRESSURE_UNIT = unit.kilojoule_per_mole / unit.nanometer**3


def check_integrator(integrator):
    """Raises TypeError unless `integrator` has the DPD pressure-tensor API."""
    if not hasattr(integrator, "getAveragePressureTensor"):
        raise TypeError(f"the pressure tensor needs a DPD integrator (a DPDThermostatIntegrator such as "
                        f"DPDVVIntegrator or ShardlowIntegrator); got {type(integrator).__name__}")


def pressure_tensor(integrator, part=0):
    """The integrator's average pressure tensor since its last reset, as a numpy array of the six
    components (xx, yy, zz, xy, xz, yz) in kJ/mol/nm^3; part is an index into PARTS."""
    value = integrator.getAveragePressureTensor(part)
    if unit.is_quantity(value):
        value = value.value_in_unit(PRESSURE_UNIT)
    return np.array([v.value_in_unit(PRESSURE_UNIT) if unit.is_quantity(v) else v for v in value], dtype=float)


class PressureTensorReporter:
    """Writes the pressure tensor of a Simulation with a DPD integrator to a CSV file.

    Each row is a block average: the mean over the reportInterval steps since the previous row
    (each step samples the tensor once, at its end), because the reporter resets the
    integrator's average after every report.  The first row averages from the step the
    reporter was first asked about (it enables the tensor and resets it then), so it is
    shorter when the Simulation's step count is not a multiple of reportInterval.

    Columns: step, time_ps, Pxx, Pyy, Pzz, Pxy, Pxz, Pyz (kJ/mol/nm^3, = kT/rc^3 in reduced
    units); with parts=True also kinetic_Pxx ... thermostat_Pyz, the kinetic (peculiar
    velocities), conservative and thermostat (dissipative + random) parts, which sum to the
    total.  The integrator keeps the tensor enabled afterwards (it costs a pass over the
    pairs per step: `integrator.setPressureTensorEnabled(False)` to stop paying for it).

    file: a path (opened for writing) or an open text file.
    """

    def __init__(self, file, reportInterval, parts=False):
        if isinstance(reportInterval, bool) or not isinstance(reportInterval, (int, np.integer)) or reportInterval < 1:
            raise ValueError(f"PressureTensorReporter: reportInterval must be an integer >= 1 step, got {reportInterval!r}")
        self._interval = int(reportInterval)
        self._parts = range(len(PARTS)) if parts else range(1)
        self._own_file = isinstance(file, str)
        self._out = open(file, "w") if self._own_file else file
        self._started = False

    def _header(self):
        names = [f"P{c}" for c in COMPONENTS]
        columns = ["step", "time_ps"] + names
        columns += [f"{PARTS[p]}_{name}" for p in self._parts if p > 0 for name in names]
        self._out.write(",".join(columns) + "\n")

    def _start(self, integrator):
        check_integrator(integrator)
        integrator.setPressureTensorEnabled(True)
        integrator.resetPressureTensor()
        self._header()
        self._started = True

    def describeNextReport(self, simulation):
        """(steps to the next report, positions, velocities, forces, energies): no state data needed."""
        if not self._started:
            self._start(simulation.integrator)
        steps = self._interval - simulation.currentStep % self._interval
        return (steps, False, False, False, False)

    def report(self, simulation, state):
        """Writes the block average since the last report, then resets the integrator's average."""
        integrator = simulation.integrator
        values = [simulation.currentStep, state.getTime().value_in_unit(unit.picosecond)]
        for part in self._parts:
            values.extend(pressure_tensor(integrator, part))
        integrator.resetPressureTensor()
        self._out.write(",".join(repr(float(v)) if k else str(v) for k, v in enumerate(values)) + "\n")
        self._out.flush()

    def __del__(self):
        if getattr(self, "_own_file", False):
            self._out.close()
