%module(package="openmmdpd") dpdplugin

%import(module="openmm.openmm") "openmm_stub.i"

%{
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/OpenMMException.h"
#include <exception>
%}

%include "typemaps.i"
%include "std_map.i"
%include "std_string.i"
%include "std_vector.i"
%template(ParticleTypeMap) std::map<int, int>;
%template(IntVector) std::vector<int>;

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
%}

// --- units in: every dimensioned argument accepts a Quantity or a number in OpenMM units ---
%pythonprepend DPDPlugin::DPDVVIntegrator::DPDVVIntegrator %{
    temperature = _strip(temperature, _unit.kelvin)
    defaultFriction = _strip(defaultFriction, _unit.picosecond**-1)
    defaultCutoff = _strip(defaultCutoff, _unit.nanometer)
    stepSize = _strip(stepSize, _unit.picosecond)
%}
%pythonprepend DPDPlugin::ShardlowIntegrator::ShardlowIntegrator %{
    temperature = _strip(temperature, _unit.kelvin)
    defaultFriction = _strip(defaultFriction, _unit.picosecond**-1)
    defaultCutoff = _strip(defaultCutoff, _unit.nanometer)
    stepSize = _strip(stepSize, _unit.picosecond)
%}
%pythonprepend DPDPlugin::LoweAndersenIntegrator::LoweAndersenIntegrator %{
    temperature = _strip(temperature, _unit.kelvin)
    defaultGamma = _strip(defaultGamma, _unit.picosecond**-1)
    defaultCutoff = _strip(defaultCutoff, _unit.nanometer)
    stepSize = _strip(stepSize, _unit.picosecond)
%}
%pythonprepend DPDPlugin::EDPDIntegrator::EDPDIntegrator %{
    temperature = _strip(temperature, _unit.kelvin)
    defaultFriction = _strip(defaultFriction, _unit.picosecond**-1)
    defaultCutoff = _strip(defaultCutoff, _unit.nanometer)
    alpha = _strip(alpha, _unit.picosecond**-1)
    stepSize = _strip(stepSize, _unit.picosecond)
%}
%pythonprepend DPDPlugin::EDPDIntegrator::setAlpha %{
    alpha = _strip(alpha, _unit.picosecond**-1)
%}
%pythonappend DPDPlugin::EDPDIntegrator::getAlpha %{
    val = _unit.Quantity(val, _unit.picosecond**-1)
%}
%pythonappend DPDPlugin::EDPDIntegrator::getPairVariable %{
    val = _unit.Quantity(val, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonprepend DPDPlugin::StaggeredDPDIntegrator::StaggeredDPDIntegrator %{
    temperature = _strip(temperature, _unit.kelvin)
    defaultFriction = _strip(defaultFriction, _unit.picosecond**-1)
    defaultCutoff = _strip(defaultCutoff, _unit.nanometer)
    stepSize = _strip(stepSize, _unit.picosecond)
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
    defaultA = _strip(defaultA, _unit.kilojoule_per_mole / _unit.nanometer)
    defaultCutoff = _strip(defaultCutoff, _unit.nanometer)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::setDefaultA %{
    a = _strip(a, _unit.kilojoule_per_mole / _unit.nanometer)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::setDefaultCutoff %{
    cutoff = _strip(cutoff, _unit.nanometer)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::addTypePair %{
    a = _strip(a, _unit.kilojoule_per_mole / _unit.nanometer)
    cutoff = _strip(cutoff, _unit.nanometer)
%}
%pythonprepend DPDPlugin::DPDSoftRepulsionForce::setTypePairParameters %{
    a = _strip(a, _unit.kilojoule_per_mole / _unit.nanometer)
    cutoff = _strip(cutoff, _unit.nanometer)
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
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setTemperature %{
    temp = _strip(temp, _unit.kelvin)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setDefaultFriction %{
    friction = _strip(friction, _unit.picosecond**-1)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setDefaultCutoff %{
    cutoff = _strip(cutoff, _unit.nanometer)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setStepSize %{
    size = _strip(size, _unit.picosecond)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::addTypePair %{
    friction = _strip(friction, _unit.picosecond**-1)
    cutoff = _strip(cutoff, _unit.nanometer)
%}
%pythonprepend DPDPlugin::DPDThermostatIntegrator::setTypePairParameters %{
    friction = _strip(friction, _unit.picosecond**-1)
    cutoff = _strip(cutoff, _unit.nanometer)
%}

// --- units out: getters return Quantities, like OpenMM's ---
%pythonappend DPDPlugin::DPDThermostatIntegrator::getTemperature %{
    val = _unit.Quantity(val, _unit.kelvin)
%}
%pythonappend DPDPlugin::DPDThermostatIntegrator::getDefaultFriction %{
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
%apply double& OUTPUT { double& friction, double& cutoff, double& a };

// Only the public interface: the protected Integrator hooks are for OpenMM.
%ignore DPDPlugin::DPDThermostatIntegrator::validate;
%ignore DPDPlugin::LoweAndersenIntegrator::validate;
%ignore DPDPlugin::StaggeredDPDIntegrator::validate;
%ignore DPDPlugin::DPDSoftRepulsionForce::getTypeTable;

%include "openmmdpd/DPDThermostatIntegrator.h"
%include "openmmdpd/DPDVVIntegrator.h"
%include "openmmdpd/ShardlowIntegrator.h"
%include "openmmdpd/LoweAndersenIntegrator.h"
%include "openmmdpd/EDPDIntegrator.h"
%include "openmmdpd/StaggeredDPDIntegrator.h"
%include "openmmdpd/DPDSoftRepulsionForce.h"

%clear int& type1, int& type2, int& particle1, int& particle2;
%clear double& friction, double& cutoff, double& a;

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
DPD_EXTRAS(StaggeredDPDIntegrator, OpenMM::Integrator)
DPD_EXTRAS(DPDSoftRepulsionForce, OpenMM::Force)
