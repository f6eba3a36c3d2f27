"""The warning when an integrator is given a temperature that is almost surely a reduced kT read
as kelvin (0 < T < 10 K): every integrator class, at construction and in setTemperature, once
per line of code, with the standard opt-out, and nothing else changed (copies, pickles, XML,
cast, signatures)."""
import copy
import inspect
import os
import pickle
import subprocess
import sys
import warnings

import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import LowTemperatureWarning

NM, K = unit.nanometer, unit.kelvin


MAKERS = {
    "DPDVVIntegrator": lambda T: openmmdpd.DPDVVIntegrator(T, 4.5, 1.0, 0.01),
    "ShardlowIntegrator": lambda T: openmmdpd.ShardlowIntegrator(T, 4.5, 1.0, 0.04),
    "LoweAndersenIntegrator": lambda T: openmmdpd.LoweAndersenIntegrator(T, 4.5, 1.0, 0.02),
    "EDPDIntegrator": lambda T: openmmdpd.EDPDIntegrator(T, 4.5, 1.0, 0.5, 0.01),
    "DenOtterClarkeIntegrator": lambda T: openmmdpd.DenOtterClarkeIntegrator(T, 4.5, 1.0, 0.02),
    "StaggeredDPDIntegrator": lambda T: openmmdpd.StaggeredDPDIntegrator(T, 4.5, 1.0, 0.02, 2),
}


@pytest.fixture(autouse=True)
def fresh_warning_state():
    """Each line warns once per process; each test starts as a fresh process would."""
    openmmdpd._low_temperature._warned_at.clear()
    yield
    openmmdpd._low_temperature._warned_at.clear()


def recorded(action):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = action()
    return result, [w for w in caught if issubclass(w.category, LowTemperatureWarning)]


def test_every_integrator_class_of_the_package_is_covered():
    classes = {name for name in openmmdpd.__all__ if name.endswith("Integrator")} - {"DPDThermostatIntegrator"}
    assert classes == set(MAKERS)


@pytest.mark.parametrize("name", list(MAKERS))
def test_a_reduced_kT_given_as_kelvin_warns_at_construction(name):
    _, caught = recorded(lambda: MAKERS[name](1.0))
    assert len(caught) == 1
    text = str(caught[0].message)
    assert text.startswith(f"{name}: temperature 1 K is kT = 0.008314 kJ/mol")
    assert "openmmdpd.reduced_temperature(1.0)" in text and "DPDUnits().temperature(1.0)" in text
    assert 'warnings.filterwarnings("ignore", category=openmmdpd.LowTemperatureWarning)' in text
    assert caught[0].filename == __file__  # the user's line, not the package's
    assert issubclass(LowTemperatureWarning, UserWarning)


@pytest.mark.parametrize("name", list(MAKERS))
def test_a_reduced_kT_given_as_kelvin_warns_in_setTemperature(name):
    integrator = MAKERS[name](openmmdpd.KT_TEMPERATURE)
    _, caught = recorded(lambda: integrator.setTemperature(2.0 * K))
    assert len(caught) == 1 and str(caught[0].message).startswith(f"{name}.setTemperature: temperature 2 K is kT")
    assert integrator.getTemperature() == 2.0 * K  # the warning changes nothing


@pytest.mark.parametrize("temperature", [0.0, 10.0, 10 * K, openmmdpd.KT_TEMPERATURE, 300.0])
def test_zero_and_real_temperatures_do_not_warn(temperature):
    with warnings.catch_warnings():
        warnings.simplefilter("error", LowTemperatureWarning)
        for make in MAKERS.values():
            make(temperature).setTemperature(temperature)


def test_just_below_ten_kelvin_warns():
    _, caught = recorded(lambda: openmmdpd.ShardlowIntegrator(9.99 * K, 4.5, 1.0, 0.04))
    assert len(caught) == 1 and "temperature 9.99 K is kT = 0.08306 kJ/mol" in str(caught[0].message)


def test_a_loop_warns_once():
    """Once per line of code, whatever the value and even with the filter "always"."""
    def sweep():
        for i in range(200):
            integrator = openmmdpd.DPDVVIntegrator(0.5 + 0.01 * i, 4.5, 1.0, 0.01)
            integrator.setTemperature(1.0 + 0.01 * i)
    _, caught = recorded(sweep)
    assert [str(w.message).split(":")[0] for w in caught] == ["DPDVVIntegrator", "DPDVVIntegrator.setTemperature"]
    assert "temperature 0.5 K" in str(caught[0].message) and "temperature 1 K" in str(caught[1].message)


def test_a_loop_under_pythons_default_filter_prints_one_warning():
    code = ("import openmmdpd\n"
            "for i in range(500):\n"
            "    integrator = openmmdpd.ShardlowIntegrator(1.0 + i / 100, 4.5, 1.0, 0.04)\n"
            "    integrator.setTemperature(2.0)\n"
            "print('done')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)))
    env.pop("PYTHONWARNINGS", None)
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and result.stdout.split() == ["done"], result.stderr
    # The constructor's and setTemperature's.
    assert result.stderr.count(": LowTemperatureWarning: ") == 2, result.stderr


def test_the_standard_filter_opts_out():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=LowTemperatureWarning)
        openmmdpd.ShardlowIntegrator(1.0, 4.5, 1.0, 0.04)
    assert not caught


def test_a_warned_integrator_still_copies_pickles_serializes_and_casts():
    integrator, caught = recorded(lambda: openmmdpd.ShardlowIntegrator(5.0, 4.5, 1.0, 0.04))
    assert len(caught) == 1
    # Making these does not run the constructor, so they do not warn again.
    with warnings.catch_warnings():
        warnings.simplefilter("error", LowTemperatureWarning)
        for again in (copy.copy(integrator), copy.deepcopy(integrator), pickle.loads(pickle.dumps(integrator)),
                      openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(integrator)),
                      openmmdpd.ShardlowIntegrator.cast(openmm.XmlSerializer.clone(integrator))):
            assert type(again) is openmmdpd.ShardlowIntegrator and again.getTemperature() == 5.0 * K


def test_the_wrapped_methods_keep_their_signatures_and_docs():
    init = openmmdpd.EDPDIntegrator.__init__
    assert list(inspect.signature(init).parameters) == ["self", "temperature", "defaultFriction", "defaultCutoff",
                                                         "alpha", "stepSize"]
    assert ":param temperature:" in init.__doc__
    assert "temperature" in openmmdpd.DPDThermostatIntegrator.setTemperature.__doc__


def test_bad_temperatures_raise_before_any_warning():
    _, caught = recorded(lambda: pytest.raises(openmm.OpenMMException, openmmdpd.DPDVVIntegrator, -1.0, 4.5, 1.0,
                                               0.01))
    assert not caught
    with pytest.raises(TypeError, match="temperature"):
        openmmdpd.DPDVVIntegrator(1.0 * NM, 4.5, 1.0, 0.01)
