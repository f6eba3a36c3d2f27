"""Bad arguments: a wrong unit or type names the class, method and parameter, and
range errors print numbers as they were written ("ClassName: parameter must be ..., got X")."""
import openmm
import pytest
from openmm import unit

import openmmdpd

PS, NM, K = unit.picosecond, unit.nanometer, unit.kelvin
FORCE = unit.kilojoule_per_mole / unit.nanometer
INTEGRATORS = [openmmdpd.DPDVVIntegrator, openmmdpd.ShardlowIntegrator, openmmdpd.LoweAndersenIntegrator,
               openmmdpd.EDPDIntegrator, openmmdpd.StaggeredDPDIntegrator, openmmdpd.DenOtterClarkeIntegrator]

# Every constructor's arguments, by name, with good values.
THERMOSTAT = {"temperature": 300 * K, "defaultFriction": 4.5 / PS, "defaultCutoff": 1 * NM, "stepSize": 0.01 * PS}
CONSTRUCTORS = {
    openmmdpd.DPDVVIntegrator: THERMOSTAT,
    openmmdpd.ShardlowIntegrator: THERMOSTAT,
    openmmdpd.LoweAndersenIntegrator: {"temperature": 300 * K, "defaultGamma": 4.5 / PS, "defaultCutoff": 1 * NM,
                                       "stepSize": 0.01 * PS},
    openmmdpd.EDPDIntegrator: {"temperature": 300 * K, "defaultFriction": 4.5 / PS, "defaultCutoff": 1 * NM,
                               "alpha": 1 / PS, "stepSize": 0.01 * PS},
    openmmdpd.StaggeredDPDIntegrator: THERMOSTAT,
    openmmdpd.DenOtterClarkeIntegrator: THERMOSTAT,
    openmmdpd.DPDSoftRepulsionForce: {"defaultA": 25 * FORCE, "defaultCutoff": 1 * NM},
}

# (method, good arguments, {position of a checked argument: the name its errors give}).
THERMOSTAT_SETTERS = [
    ("setTemperature", [300 * K], {0: "temperature"}),
    ("setDefaultFriction", [4.5 / PS], {0: "defaultFriction"}),
    ("setDefaultCutoff", [1 * NM], {0: "defaultCutoff"}),
    ("setStepSize", [0.01 * PS], {0: "stepSize"}),
    ("addTypePair", [0, 1, 4.5 / PS, 1 * NM], {2: "friction", 3: "cutoff"}),
    ("setTypePairParameters", [0, 0, 1, 4.5 / PS, 1 * NM], {3: "friction", 4: "cutoff"}),
]
SETTERS = {cls: THERMOSTAT_SETTERS for cls in INTEGRATORS}
SETTERS[openmmdpd.DPDVVIntegrator] = THERMOSTAT_SETTERS + [
    ("setLambda", [0.5], {0: "lambda"}),
    ("setTolerance", [1e-6], {0: "tolerance"}),
]
SETTERS[openmmdpd.EDPDIntegrator] = THERMOSTAT_SETTERS + [("setAlpha", [1 / PS], {0: "alpha"})]
SETTERS[openmmdpd.StaggeredDPDIntegrator] = THERMOSTAT_SETTERS + [
    ("setLambda", [0.5], {0: "lambda"}),
    ("setMu", [0.0], {0: "mu"}),
    ("setA", [0.6], {0: "a"}),
    ("setB", [0.0], {0: "b"}),
    ("setRelaxationParameters", [0.0, 0.6, 0.0], {0: "mu", 1: "a", 2: "b"}),
]
POWER = unit.kilojoule_per_mole / PS
SETTERS[openmmdpd.DenOtterClarkeIntegrator] = THERMOSTAT_SETTERS + [
    ("setAverageFDDotV", [-4.985245 * POWER], {0: "averageFDDotV"}),
    ("setAverageFDDotFD", [14.507340 * FORCE**2], {0: "averageFDDotFD"}),
    ("setAverageFRDotFR", [9.976453 * FORCE**2 * PS], {0: "averageFRDotFR"}),
]
SETTERS[openmmdpd.DPDSoftRepulsionForce] = [
    ("setDefaultA", [25 * FORCE], {0: "defaultA"}),
    ("setDefaultCutoff", [1 * NM], {0: "defaultCutoff"}),
    ("addTypePair", [0, 1, 25 * FORCE, 1 * NM], {2: "a", 3: "cutoff"}),
    ("setTypePairParameters", [0, 0, 1, 25 * FORCE, 1 * NM], {3: "a", 4: "cutoff"}),
]


def wrong_values(good):
    """A Quantity in units of another dimension, then values of wrong types."""
    wrong_unit = 2.5 * K if unit.is_quantity(good) and good.unit.is_compatible(NM) else 2.5 * NM
    return [wrong_unit, "1.5", None, [1.0]]


def make(cls):
    return cls(*CONSTRUCTORS[cls].values())


CONSTRUCTOR_CASES = [pytest.param(cls, name, bad, id=f"{cls.__name__}-{name}-{bad!r}")
                     for cls, arguments in CONSTRUCTORS.items()
                     for name, good in arguments.items() for bad in wrong_values(good)]
SETTER_CASES = [pytest.param(cls, method, args, position, name, bad, id=f"{cls.__name__}.{method}-{name}-{bad!r}")
                for cls, setters in SETTERS.items() for method, args, checked in setters
                for position, name in checked.items() for bad in wrong_values(args[position])]


def expect_type_error(action, where, name, bad):
    shown = str(bad) if unit.is_quantity(bad) else repr(bad)
    with pytest.raises(TypeError) as error:
        action()
    assert str(error.value).startswith(f"{where}: {name} must be "), str(error.value)
    assert str(error.value).endswith(f", got {shown}"), str(error.value)


@pytest.mark.parametrize("cls, name, bad", CONSTRUCTOR_CASES)
def test_constructor_argument_of_wrong_unit_or_type_is_named(cls, name, bad):
    arguments = dict(CONSTRUCTORS[cls], **{name: bad})
    expect_type_error(lambda: cls(**arguments), cls.__name__, name, bad)


@pytest.mark.parametrize("cls, method, args, position, name, bad", SETTER_CASES)
def test_setter_argument_of_wrong_unit_or_type_is_named(cls, method, args, position, name, bad):
    target = make(cls)
    if method == "setTypePairParameters":
        target.addTypePair(*args[1:])
    getattr(target, method)(*args)  # the good arguments are accepted
    bad_args = args[:position] + [bad] + args[position + 1:]
    expect_type_error(lambda: getattr(target, method)(*bad_args), f"{cls.__name__}.{method}", name, bad)


@pytest.mark.parametrize("cls, action, expected", [
    (openmmdpd.DPDSoftRepulsionForce, lambda f: f.setDefaultCutoff(-1.5), "defaultCutoff must be > 0 nm, got -1.5"),
    (openmmdpd.DPDSoftRepulsionForce, lambda f: f.addTypePair(0, 1, -0.1, 1), "a must be >= 0 kJ/mol/nm, got -0.1"),
    (openmmdpd.DPDVVIntegrator, lambda i: i.setDefaultCutoff(-1.5), "defaultCutoff must be > 0 nm, got -1.5"),
    (openmmdpd.ShardlowIntegrator, lambda i: i.setTemperature(-0.1), "temperature must be >= 0 K, got -0.1"),
    (openmmdpd.LoweAndersenIntegrator, lambda i: i.setStepSize(-3e-7), "stepSize must be > 0 ps, got -3e-07"),
    (openmmdpd.EDPDIntegrator, lambda i: i.setAlpha(-1.2), "alpha must be > 0 /ps, got -1.2"),
    (openmmdpd.DPDVVIntegrator, lambda i: i.setLambda(1.2), "lambda must be in [0, 1], got 1.2"),
    (openmmdpd.DPDVVIntegrator, lambda i: i.setTolerance(-1e-6), "tolerance must be >= 0, got -1e-06"),
    (openmmdpd.StaggeredDPDIntegrator, lambda i: i.setA(1.0000001), "a must be in [-1, 1], got 1.0000001"),
    (openmmdpd.DenOtterClarkeIntegrator, lambda i: i.setAverageFDDotV(0.25),
     "averageFDDotV must be < 0 kJ/mol/ps (friction takes energy out), got 0.25"),
    (openmmdpd.DenOtterClarkeIntegrator, lambda i: i.setAverageFRDotFR(-1e-3), "averageFRDotFR must be > 0 (kJ/mol/nm)^2 ps, got -0.001"),
    (openmmdpd.StaggeredDPDIntegrator, lambda i: i.addTypePair(0, 1, 2.5, -0.75),
     "cutoff must be > 0 nm, got -0.75"),
])
def test_range_error_prints_the_number_as_written(cls, action, expected):
    with pytest.raises(openmm.OpenMMException) as error:
        action(make(cls))
    assert str(error.value) == f"{cls.__name__}: {expected}"


def test_context_time_error_prints_numbers_as_written():
    system = openmm.System()
    for _ in range(2):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) * 2.5 for row in [(1, 0, 0), (0, 1, 0), (0, 0, 1)]))
    system.addForce(openmmdpd.DPDSoftRepulsionForce(25, 1))
    integrator = openmmdpd.LoweAndersenIntegrator(300, 150, 1.3, 0.01)
    with pytest.raises(openmm.OpenMMException) as error:
        openmm.Context(system, integrator, openmm.Platform.getPlatformByName("Reference"))
    assert str(error.value) == ("LoweAndersenIntegrator: the thermostat cutoff must be <= half the periodic box width "
                                "(1.25 nm), got 1.3 nm")
    integrator.setDefaultCutoff(1)
    with pytest.raises(openmm.OpenMMException) as error:
        openmm.Context(system, integrator, openmm.Platform.getPlatformByName("Reference"))
    assert str(error.value).endswith("the largest Gamma (150 /ps) times the step size (0.01 ps) = 1.5")
