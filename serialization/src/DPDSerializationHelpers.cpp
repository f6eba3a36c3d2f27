#include "openmmdpd/DPDSerializationHelpers.h"
#include "openmm/serialization/SerializationNode.h"

using namespace DPDPlugin;
using OpenMM::SerializationNode;

void DPDPlugin::serializeThermostatParameters(const DPDThermostatIntegrator& integrator, SerializationNode& node) {
    node.setDoubleProperty("stepSize", integrator.getStepSize());
    node.setDoubleProperty("temperature", integrator.getTemperature());
    node.setDoubleProperty("defaultFriction", integrator.getDefaultFriction());
    node.setDoubleProperty("defaultCutoff", integrator.getDefaultCutoff());
    node.setIntProperty("randomSeed", integrator.getRandomNumberSeed());
    node.setIntProperty("integrationForceGroups", integrator.getIntegrationForceGroups());
    node.setDoubleProperty("instabilityThreshold", integrator.getInstabilityThreshold());
    node.setDoubleProperty("shearRate", integrator.getShearRate());
    node.setBoolProperty("pressureTensorEnabled", integrator.getPressureTensorEnabled());
    serializeTypeTable(integrator, node, "friction");
}

void DPDPlugin::deserializeThermostatParameters(const SerializationNode& node, DPDThermostatIntegrator& integrator) {
    integrator.setRandomNumberSeed(node.getIntProperty("randomSeed"));
    integrator.setIntegrationForceGroups(node.getIntProperty("integrationForceGroups"));
    // XML written before the sentinel existed has no threshold: off, as it was.
    integrator.setInstabilityThreshold(node.getDoubleProperty("instabilityThreshold", 0.0));
    // XML written before shear existed has none.
    integrator.setShearRate(node.getDoubleProperty("shearRate", 0.0));
    integrator.setPressureTensorEnabled(node.getBoolProperty("pressureTensorEnabled", false));
    deserializeTypeTable(node, integrator, "friction");
}
