"""Every integrator the tools compare, by name, built the same way everywhere: ours, OpenMM's
LangevinMiddleIntegrator (the baseline users know) and OpenMM's own DPDIntegrator where the
installed OpenMM has one (8.3 and later).  Friction 4.5/ps (= gamma for unit masses, and
Lowe's collision rate), cutoff 1 nm, kT = 1 kJ/mol."""
import openmm

from . import DenOtterClarkeIntegrator, DPDVVIntegrator, LoweAndersenIntegrator, ShardlowIntegrator
from .calibration import PAPER_000_TABLE_III
from .units import KT_TEMPERATURE

FRICTION = 4.5  # 1/ps
CUTOFF = 1.0    # nm, the DPD rc
# The recommended instability threshold (DPDThermostatIntegrator.setInstabilityThreshold), in kT:
# a thermal particle passes 40 kT about once in 3e16 particle-steps, a blow-up far sooner.
INSTABILITY_THRESHOLD = 40.0


def _dpdvv(variant, lam=0.5):
    def make(dt):
        integrator = DPDVVIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, dt)
        integrator.setVariant(variant)
        integrator.setLambda(lam)
        return integrator
    return make


def _shardlow(order):
    def make(dt):
        integrator = ShardlowIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, dt)
        integrator.setOrder(order)
        return integrator
    return make


def _lowe(method, splitting=LoweAndersenIntegrator.AfterVerlet):
    def make(dt):
        integrator = LoweAndersenIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, dt)
        integrator.setMethod(method)
        integrator.setSplitting(splitting)
        return integrator
    return make


def _den_otter_clarke(averages):
    def make(dt):
        integrator = DenOtterClarkeIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, dt)
        integrator.setAverageFDDotV(averages[0])
        integrator.setAverageFDDotFD(averages[1])
        integrator.setAverageFRDotFR(averages[2])
        return integrator
    return make


def integrators(scene=None):
    """{name: factory(dt) -> Integrator}, in the order the tools report them.  With the name
    of a scene Nikunen et al. 2003 calibrated (ideal, soft, polymer), also den Otter-Clarke ("OC") with
    the paper's Table III averages."""
    factories = {
        "Langevin": lambda dt: openmm.LangevinMiddleIntegrator(KT_TEMPERATURE, FRICTION, dt),
        "GW": _dpdvv(DPDVVIntegrator.GrootWarren),
        "GW0.65": _dpdvv(DPDVVIntegrator.GrootWarren, 0.65),
        "DPD-VV": _dpdvv(DPDVVIntegrator.DPDVV),
        "SC-VV": _dpdvv(DPDVVIntegrator.SelfConsistent),
        "S1": _shardlow(1),
        "S2": _shardlow(2),
        "Lowe": _lowe(LoweAndersenIntegrator.Lowe),
        "PairOU": _lowe(LoweAndersenIntegrator.PairOrnsteinUhlenbeck),
        "Lowe-mid": _lowe(LoweAndersenIntegrator.Lowe, LoweAndersenIntegrator.Middle),
        "PairOU-mid": _lowe(LoweAndersenIntegrator.PairOrnsteinUhlenbeck, LoweAndersenIntegrator.Middle),
    }
    if scene in PAPER_000_TABLE_III:
        factories["OC"] = _den_otter_clarke(PAPER_000_TABLE_III[scene])
    if hasattr(openmm, "DPDIntegrator"):
        factories["OpenMM-DPD"] = lambda dt: openmm.DPDIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, dt)
    return factories
