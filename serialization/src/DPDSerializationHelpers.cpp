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
    SerializationNode& types = node.createChildNode("ParticleTypes");
    for (auto& entry : integrator.getParticleTypes())
        types.createChildNode("Particle").setIntProperty("index", entry.first).setIntProperty("type", entry.second);
    SerializationNode& pairs = node.createChildNode("TypePairs");
    for (int k = 0; k < integrator.getNumTypePairs(); k++) {
        int t1, t2;
        double friction, cutoff;
        integrator.getTypePairParameters(k, t1, t2, friction, cutoff);
        pairs.createChildNode("TypePair").setIntProperty("type1", t1).setIntProperty("type2", t2)
                .setDoubleProperty("friction", friction).setDoubleProperty("cutoff", cutoff);
    }
}

void DPDPlugin::deserializeThermostatParameters(const SerializationNode& node, DPDThermostatIntegrator& integrator) {
    integrator.setRandomNumberSeed(node.getIntProperty("randomSeed"));
    integrator.setIntegrationForceGroups(node.getIntProperty("integrationForceGroups"));
    for (const SerializationNode& p : node.getChildNode("ParticleTypes").getChildren())
        integrator.setParticleType(p.getIntProperty("index"), p.getIntProperty("type"));
    for (const SerializationNode& p : node.getChildNode("TypePairs").getChildren())
        integrator.addTypePair(p.getIntProperty("type1"), p.getIntProperty("type2"), p.getDoubleProperty("friction"),
                               p.getDoubleProperty("cutoff"));
}
