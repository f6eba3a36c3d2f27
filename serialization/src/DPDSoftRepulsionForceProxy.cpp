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
    serializeTypeTable(force, node, "a");
    SerializationNode& exclusions = node.createChildNode("Exclusions");
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        exclusions.createChildNode("Exclusion").setIntProperty("p1", p1).setIntProperty("p2", p2);
    }
}

void* DPDSoftRepulsionForceProxy::deserialize(const SerializationNode& node) const {
    const XmlReader xml(node, "DPDSoftRepulsionForce");
    const int version = xml.integer("version");
    if (version != 1)
        throw OpenMM::OpenMMException("DPDSoftRepulsionForce: the XML version must be 1, got " + std::to_string(version));
    DPDSoftRepulsionForce* force = new DPDSoftRepulsionForce(xml.number("defaultA"), xml.number("defaultCutoff"));
    try {
        force->setForceGroup(xml.integer("forceGroup"));
        force->setNonbondedMethod((DPDSoftRepulsionForce::NonbondedMethod) xml.integer("method"));
        deserializeTypeTable(xml, *force, "a");
        for (const XmlReader& e : xml.child("Exclusions").children())
            force->addExclusion(e.integer("p1"), e.integer("p2"));
    }
    catch (...) {
        delete force;
        throw;
    }
    return force;
}
