%module(package="openmmdpd") dpdplugin

%import(module="openmm.openmm") "openmm_stub.i"

%{
#include "openmmdpd/Checkpoints.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/OpenMMException.h"
#include <exception>
#include <sstream>
%}

%include "typemaps.i"
%include "std_map.i"
%include "std_pair.i"
%include "std_string.i"
%include "std_vector.i"
%template(ParticleTypeMap) std::map<int, int>;
%template(IntVector) std::vector<int>;
%template(DoubleVector) std::vector<double>;
%template(IntPair) std::pair<int, int>;
%template(IntPairVector) std::vector<std::pair<int, int>>;

// Errors reach Python as openmm.OpenMMException, as OpenMM's own do.
%exception {
    try {
        $action
    }
    catch (std::exception& e) {
        PyObject* module = PyImport_ImportModule("openmm");
        PyObject* type = module ? PyObject_GetAttrString(module, "OpenMMException") : NULL;
        Py_XDECREF(module);
        PyErr_SetString(type ? type : PyExc_Exception, e.what());
        Py_XDECREF(type);
        SWIG_fail;
    }
}

%pythonbegin %{
import openmm as _mm
from openmm import unit as _unit
from openmmdpd.units import strip_units as _strip

_K, _NM, _PS = _unit.kelvin, _unit.nanometer, _unit.picosecond
_RATE, _FORCE = _unit.picosecond**-1, _unit.kilojoule_per_mole / _unit.nanometer
_PRESSURE = _unit.kilojoule_per_mole / _unit.nanometer**3
# den Otter-Clarke's averages: <FD.v> (a power), <FD.FD>, <FR.FR> (FR without 1/sqrt(dt))
_POWER, _FORCE2, _FORCE2_TIME = _unit.kilojoule_per_mole / _unit.picosecond, _FORCE**2, _FORCE**2 * _unit.picosecond


def _arg(self, method, name, value, target_unit):
    """value as a float in target_unit (None: a plain number), or a TypeError that names the
    class, the method (None: the constructor) and the parameter it was given to."""
    where = type(self).__name__ + ("" if method is None else "." + method)
    return _strip(value, target_unit, name, where)
%}

// --- units in: every dimensioned argument accepts a Quantity or a number in OpenMM units.  A bad
// one raises TypeError "Class.method: name must be ..., got X", name as in the C++ range errors.
%pythonprepend DPDPlugin::DPDVVIntegrator::DPDVVIntegrator %{
    temperature = _arg(self, None, "temperature", temperature, _K)
    defaultFriction = _arg(self, None, "defaultFriction", defaultFriction, _RATE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    stepSize = _arg(self, None, "stepSize", stepSize, _PS)
%}
%pythonprepend DPDPlugin::ShardlowIntegrator::ShardlowIntegrator %{
    temperature = _arg(self, None, "temperature", temperature, _K)
    defaultFriction = _arg(self, None, "defaultFriction", defaultFriction, _RATE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    stepSize = _arg(self, None, "stepSize", stepSize, _PS)
%}
%pythonprepend DPDPlugin::LoweAndersenIntegrator::LoweAndersenIntegrator %{
    temperature = _arg(self, None, "temperature", temperature, _K)
    defaultGamma = _arg(self, None, "defaultGamma", defaultGamma, _RATE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    stepSize = _arg(self, None, "stepSize", stepSize, _PS)
%}
%pythonprepend DPDPlugin::DenOtterClarkeIntegrator::DenOtterClarkeIntegrator %{
    temperature = _arg(self, None, "temperature", temperature, _K)
    defaultFriction = _arg(self, None, "defaultFriction", defaultFriction, _RATE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    stepSize = _arg(self, None, "stepSize", stepSize, _PS)
%}
%pythonprepend DPDPlugin::DenOtterClarkeIntegrator::setAverageFDDotV %{
    value = _arg(self, "setAverageFDDotV", "averageFDDotV", value, _POWER)
%}
%pythonprepend DPDPlugin::DenOtterClarkeIntegrator::setAverageFDDotFD %{
    value = _arg(self, "setAverageFDDotFD", "averageFDDotFD", value, _FORCE2)
%}
%pythonprepend DPDPlugin::DenOtterClarkeIntegrator::setAverageFRDotFR %{
    value = _arg(self, "setAverageFRDotFR", "averageFRDotFR", value, _FORCE2_TIME)
%}
%pythonprepend DPDPlugin::DenOtterClarkeIntegrator::getPrefactors %{
    mass = _arg(self, "getPrefactors", "mass", mass, _unit.dalton)
%}
%pythonappend DPDPlugin::DenOtterClarkeIntegrator::getAverageFDDotV %{
    val = _unit.Quantity(val, _POWER)
%}
%pythonappend DPDPlugin::DenOtterClarkeIntegrator::getAverageFDDotFD %{
    val = _unit.Quantity(val, _FORCE2)
%}
%pythonappend DPDPlugin::DenOtterClarkeIntegrator::getAverageFRDotFR %{
    val = _unit.Quantity(val, _FORCE2_TIME)
%}
%pythonappend DPDPlugin::DenOtterClarkeIntegrator::getPrefactors %{
    val = tuple(val)
%}
%pythonappend DPDPlugin::DenOtterClarkeIntegrator::getMeasuredSums %{
    val = (_unit.Quantity(val[0], _POWER), _unit.Quantity(val[1], _FORCE2), _unit.Quantity(val[2], _FORCE2_TIME), val[3])
%}
%pythonprepend DPDPlugin::EDPDIntegrator::EDPDIntegrator %{
    temperature = _arg(self, None, "temperature", temperature, _K)
    defaultFriction = _arg(self, None, "defaultFriction", defaultFriction, _RATE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    alpha = _arg(self, None, "alpha", alpha, _RATE)
    stepSize = _arg(self, None, "stepSize", stepSize, _PS)
%}
%pythonprepend DPDPlugin::EDPDIntegrator::setAlpha %{
    alpha = _arg(self, "setAlpha", "alpha", alpha, _RATE)
%}
%pythonappend DPDPlugin::EDPDIntegrator::getAlpha %{
    val = _unit.Quantity(val, _unit.picosecond**-1)
%}
%pythonappend DPDPlugin::EDPDIntegrator::getPairVariable %{
    val = _unit.Quantity(val, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::StaggeredDPDIntegrator %{
    temperature = _arg(self, None, "temperature", temperature, _K)
    defaultFriction = _arg(self, None, "defaultFriction", defaultFriction, _RATE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    stepSize = _arg(self, None, "stepSize", stepSize, _PS)
%}
%pythonappend DPDPlugin::StaggeredDPDIntegrator::getSubStepSize %{
    val = _unit.Quantity(val, _unit.picosecond)
%}
%pythonappend DPDPlugin::StaggeredDPDIntegrator::getPolymerParticles %{
    val = tuple(val)
%}
%pythonappend DPDPlugin::StaggeredDPDIntegrator::findPolymerParticles %{
    val = tuple(val)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::DPDSoftRepulsionForce %{
    defaultA = _arg(self, None, "defaultA", defaultA, _FORCE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::setDefaultA %{
    a = _arg(self, "setDefaultA", "defaultA", a, _FORCE)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::setDefaultCutoff %{
    cutoff = _arg(self, "setDefaultCutoff", "defaultCutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::addTypePair %{
    a = _arg(self, "addTypePair", "a", a, _FORCE)
    cutoff = _arg(self, "addTypePair", "cutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::setTypePairParameters %{
    a = _arg(self, "setTypePairParameters", "a", a, _FORCE)
    cutoff = _arg(self, "setTypePairParameters", "cutoff", cutoff, _NM)
%}
%pythonappend DPDPlugin::DPDSoftRepulsionForce::getDefaultA %{
    val = _unit.Quantity(val, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonappend DPDPlugin::DPDSoftRepulsionForce::getDefaultCutoff %{
    val = _unit.Quantity(val, _unit.nanometer)
%}
%pythonappend DPDPlugin::DPDSoftRepulsionForce::getTypePairParameters %{
    val = [val[0], val[1], _unit.Quantity(val[2], _unit.kilojoule_per_mole / _unit.nanometer), _unit.Quantity(val[3], _unit.nanometer)]
%}
%pythonprepend DPDPlugin::MDPDForce::MDPDForce %{
    defaultA = _arg(self, None, "defaultA", defaultA, _FORCE)
    defaultB = _arg(self, None, "defaultB", defaultB, _FORCE)
    defaultCutoff = _arg(self, None, "defaultCutoff", defaultCutoff, _NM)
    densityCutoff = _arg(self, None, "densityCutoff", densityCutoff, _NM)
%}
%pythonprepend DPDPlugin::MDPDForce::setDefaultA %{
    a = _arg(self, "setDefaultA", "defaultA", a, _FORCE)
%}
%pythonprepend DPDPlugin::MDPDForce::setDefaultB %{
    b = _arg(self, "setDefaultB", "defaultB", b, _FORCE)
%}
%pythonprepend DPDPlugin::MDPDForce::setDefaultCutoff %{
    cutoff = _arg(self, "setDefaultCutoff", "defaultCutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::MDPDForce::setDensityCutoff %{
    cutoff = _arg(self, "setDensityCutoff", "densityCutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::MDPDForce::setTypeB %{
    b = _arg(self, "setTypeB", "b", b, _FORCE)
%}
%pythonprepend DPDPlugin::MDPDForce::addTypePair %{
    a = _arg(self, "addTypePair", "a", a, _FORCE)
    cutoff = _arg(self, "addTypePair", "cutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::MDPDForce::setTypePairParameters %{
    a = _arg(self, "setTypePairParameters", "a", a, _FORCE)
    cutoff = _arg(self, "setTypePairParameters", "cutoff", cutoff, _NM)
%}
%pythonappend DPDPlugin::MDPDForce::getDefaultA %{
    val = _unit.Quantity(val, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonappend DPDPlugin::MDPDForce::getDefaultB %{
    val = _unit.Quantity(val, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonappend DPDPlugin::MDPDForce::getTypeB %{
    val = _unit.Quantity(val, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonappend DPDPlugin::MDPDForce::getDefaultCutoff %{
    val = _unit.Quantity(val, _unit.nanometer)
%}
%pythonappend DPDPlugin::MDPDForce::getDensityCutoff %{
    val = _unit.Quantity(val, _unit.nanometer)
%}
%pythonappend DPDPlugin::MDPDForce::getTypePairParameters %{
    val = [val[0], val[1], _unit.Quantity(val[2], _unit.kilojoule_per_mole / _unit.nanometer), _unit.Quantity(val[3], _unit.nanometer)]
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setTemperature %{
    temp = _arg(self, "setTemperature", "temperature", temp, _K)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setDefaultFriction %{
    friction = _arg(self, "setDefaultFriction", "defaultFriction", friction, _RATE)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setDefaultTransverseFriction %{
    friction = _arg(self, "setDefaultTransverseFriction", "defaultTransverseFriction", friction, _RATE)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setTypePairTransverseFriction %{
    friction = _arg(self, "setTypePairTransverseFriction", "friction", friction, _RATE)
    weightExponent = _arg(self, "setTypePairTransverseFriction", "weightExponent", weightExponent, None)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setShearRate %{
    rate = _arg(self, "setShearRate", "shearRate", rate, _RATE)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setDefaultCutoff %{
    cutoff = _arg(self, "setDefaultCutoff", "defaultCutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setStepSize %{
    size = _arg(self, "setStepSize", "stepSize", size, _PS)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::addTypePair %{
    friction = _arg(self, "addTypePair", "friction", friction, _RATE)
    cutoff = _arg(self, "addTypePair", "cutoff", cutoff, _NM)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setTypePairParameters %{
    friction = _arg(self, "setTypePairParameters", "friction", friction, _RATE)
    cutoff = _arg(self, "setTypePairParameters", "cutoff", cutoff, _NM)
%}

// Dimensionless arguments: a number, or the same TypeError.
%pythonprepend DPDPlugin::DPDVVIntegrator::setLambda %{
    _lambda = _arg(self, "setLambda", "lambda", _lambda, None)
%}
%pythonprepend DPDPlugin::DPDVVIntegrator::setTolerance %{
    tol = _arg(self, "setTolerance", "tolerance", tol, None)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::setLambda %{
    value = _arg(self, "setLambda", "lambda", value, None)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::setMu %{
    value = _arg(self, "setMu", "mu", value, None)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::setA %{
    value = _arg(self, "setA", "a", value, None)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::setB %{
    value = _arg(self, "setB", "b", value, None)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::setRelaxationParameters %{
    mu = _arg(self, "setRelaxationParameters", "mu", mu, None)
    a = _arg(self, "setRelaxationParameters", "a", a, None)
    b = _arg(self, "setRelaxationParameters", "b", b, None)
%}

// --- units out: getters return Quantities, like OpenMM's ---
%pythonappend DPDPlugin::DPDThermostatIntegrator::getAveragePressureTensor %{
    val = _unit.Quantity(list(val), _PRESSURE)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getTemperature %{
    val = _unit.Quantity(val, _unit.kelvin)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getDefaultFriction %{
    val = _unit.Quantity(val, _unit.picosecond**-1)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getDefaultTransverseFriction %{
    val = _unit.Quantity(val, _unit.picosecond**-1)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getTypePairTransverseFriction %{
    val = [_unit.Quantity(val[0], _unit.picosecond**-1), val[1]]
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getShearRate %{
    val = _unit.Quantity(val, _unit.picosecond**-1)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getDefaultCutoff %{
    val = _unit.Quantity(val, _unit.nanometer)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getMaxCutoff %{
    val = _unit.Quantity(val, _unit.nanometer)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getTypePairParameters %{
    val = [val[0], val[1], _unit.Quantity(val[2], _unit.picosecond**-1), _unit.Quantity(val[3], _unit.nanometer)]
%}

%apply int& OUTPUT { int& type1, int& type2, int& particle1, int& particle2 };
%apply double& OUTPUT { double& friction, double& cutoff, double& a, double& factor, double& weightExponent };
%apply double& OUTPUT { double& alpha, double& beta, double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR };
%apply long long& OUTPUT { long long& count };

// Only the public interface: the protected Integrator hooks are for OpenMM.
%ignore DPDPlugin::DPDThermostatIntegrator::validate;
%ignore DPDPlugin::LoweAndersenIntegrator::validate;
%ignore DPDPlugin::DenOtterClarkeIntegrator::validate;
%ignore DPDPlugin::BOLTZMANN_KJ_PER_MOL_K;
%ignore DPDPlugin::StaggeredDPDIntegrator::validate;
%ignore DPDPlugin::DPDSoftRepulsionForce::getTypeTable;
%ignore DPDPlugin::MDPDForce::getTypeTable;
%ignore DPDPlugin::MDPDForce::getTypeBs;

%include "openmmdpd/DPDThermostatIntegrator.h"
%include "openmmdpd/DPDVVIntegrator.h"
%include "openmmdpd/ShardlowIntegrator.h"
%include "openmmdpd/LoweAndersenIntegrator.h"
%include "openmmdpd/EDPDIntegrator.h"
%include "openmmdpd/DenOtterClarkeIntegrator.h"
%include "openmmdpd/StaggeredDPDIntegrator.h"
%include "openmmdpd/DPDSoftRepulsionForce.h"
%include "openmmdpd/MDPDForce.h"

%clear int& type1, int& type2, int& particle1, int& particle2;
%clear double& friction, double& cutoff, double& a;
%clear double& alpha, double& beta, double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR;
%clear long long& count;

// Every integrator class (and the force) gets cast() (from a base Integrator proxy, e.g. what
// XmlSerializer.deserialize returns), pickling and copying that keep its own class.
%define DPD_EXTRAS(CLASS, BASE)
%extend DPDPlugin::CLASS {
    static DPDPlugin::CLASS* _cast(BASE* object) {
        return dynamic_cast<DPDPlugin::CLASS*>(object);
    }
    %pythoncode %{
    @staticmethod
    def cast(integrator):
        """The CLASS behind a base-class proxy (e.g. from XmlSerializer), or None.

        The result keeps `integrator` alive, which owns the C++ object, so
        `CLASS.cast(XmlSerializer.deserialize(xml))` is safe."""
        result = CLASS._cast(integrator)
        if result is not None:
            result._owner = integrator
        return result

    def __getstate__(self):
        return _mm.XmlSerializer.serialize(self)

    def __setstate__(self, state):
        base = _mm.XmlSerializer.deserialize(state)
        base.thisown = False  # this proxy takes over the C++ object
        self.this = CLASS._cast(base).this
        self.thisown = True

    def __copy__(self):
        copy = CLASS.__new__(CLASS)
        copy.__setstate__(self.__getstate__())
        return copy

    def __deepcopy__(self, memo):
        return self.__copy__()
    %}
}
%enddef

DPD_EXTRAS(DPDVVIntegrator, OpenMM::Integrator)
DPD_EXTRAS(ShardlowIntegrator, OpenMM::Integrator)
DPD_EXTRAS(LoweAndersenIntegrator, OpenMM::Integrator)
DPD_EXTRAS(EDPDIntegrator, OpenMM::Integrator)
DPD_EXTRAS(DenOtterClarkeIntegrator, OpenMM::Integrator)
DPD_EXTRAS(StaggeredDPDIntegrator, OpenMM::Integrator)
DPD_EXTRAS(DPDSoftRepulsionForce, OpenMM::Force)
DPD_EXTRAS(MDPDForce, OpenMM::Force)

// openmmdpd.load_checkpoint's C++ side: the checkpoint as Python bytes.
%inline %{
namespace DPDPlugin {
void _loadCheckpointBytes(OpenMM::Context& context, PyObject* data) {
    char* bytes;
    Py_ssize_t size;
    if (PyBytes_AsStringAndSize(data, &bytes, &size) != 0) {
        PyErr_Clear();
        throw OpenMM::OpenMMException("load_checkpoint: the checkpoint must be bytes");
    }
    std::istringstream stream(std::string(bytes, size));
    loadCheckpoint(context, stream);
}
}
%}
