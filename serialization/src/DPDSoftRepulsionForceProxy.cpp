#include "openmmdpd/DPDSerializationHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmm/OpenMMException.h"

using namespace DPDPlugin;
using OpenMM::SerializationNode;

DPDSoftRepulsionForceProxy::DPDSoftRepulsionForceProxy() : OpenMM::SerializationProxy("DPDSoftRepulsionForce") {
}

void DPDSoftRepulsionForceProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", 1);
    const DPDSoftRepulsionForce& force = *reinterpret_cast<const DPDSoftRepulsionForce*>(object);
    node.setIntProperty("forceGroup", force.getForceGroup());
    node.setDoubleProperty("defaultA", force.getDefaultA());
    node.setDoubleProperty("defaultCutoff", force.getDefaultCutoff());
    node.setIntProperty("method", force.getNonbondedMethod());
    SerializationNode& types = node.createChildNode("ParticleTypes");
    for (auto& entry : force.getParticleTypes())
        types.createChildNode("Particle").setIntProperty("index", entry.first).setIntProperty("type", entry.second);
    SerializationNode& pairs = node.createChildNode("TypePairs");
    for (int k = 0; k < force.getNumTypePairs(); k++) {
        int t1, t2;
        double a, cutoff;
        force.getTypePairParameters(k, t1, t2, a, cutoff);
        pairs.createChildNode("TypePair").setIntProperty("type1", t1).setIntProperty("type2", t2)
                .setDoubleProperty("a", a).setDoubleProperty("cutoff", cutoff);
    }
    SerializationNode& exclusions = node.createChildNode("Exclusions");
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        exclusions.createChildNode("Exclusion").setIntProperty("p1", p1).setIntProperty("p2", p2);
    }
}

void* DPDSoftRepulsionForceProxy::deserialize(const SerializationNode& node) const {
    if (node.getIntProperty("version") != 1)
        throw OpenMM::OpenMMException("Unsupported version number for DPDSoftRepulsionForce");
    DPDSoftRepulsionForce* force = new DPDSoftRepulsionForce(node.getDoubleProperty("defaultA"), node.getDoubleProperty("defaultCutoff"));
    try {
        force->setForceGroup(node.getIntProperty("forceGroup"));
        force->setNonbondedMethod((DPDSoftRepulsionForce::NonbondedMethod) node.getIntProperty("method"));
        for (const SerializationNode& p : node.getChildNode("ParticleTypes").getChildren())
            force->setParticleType(p.getIntProperty("index"), p.getIntProperty("type"));
        for (const SerializationNode& p : node.getChildNode("TypePairs").getChildren())
            force->addTypePair(p.getIntProperty("type1"), p.getIntProperty("type2"), p.getDoubleProperty("a"), p.getDoubleProperty("cutoff"));
        for (const SerializationNode& e : node.getChildNode("Exclusions").getChildren())
            force->addExclusion(e.getIntProperty("p1"), e.getIntProperty("p2"));
    }
    catch (...) {
        delete force;
        throw;
    }
    return force;
}
