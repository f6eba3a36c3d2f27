#include "openmmdpd/DPDSerializationHelpers.h"
#include "openmmdpd/MDPDForce.h"
#include "openmm/OpenMMException.h"

using namespace DPDPlugin;
using OpenMM::SerializationNode;

MDPDForceProxy::MDPDForceProxy() : OpenMM::SerializationProxy("MDPDForce") {
}

void MDPDForceProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", 1);
    const MDPDForce& force = *reinterpret_cast<const MDPDForce*>(object);
    node.setIntProperty("forceGroup", force.getForceGroup());
    node.setDoubleProperty("defaultA", force.getDefaultA());
    node.setDoubleProperty("defaultB", force.getDefaultB());
    node.setDoubleProperty("defaultCutoff", force.getDefaultCutoff());
    node.setDoubleProperty("densityCutoff", force.getDensityCutoff());
    node.setIntProperty("method", force.getNonbondedMethod());
    serializeTypeTable(force, node, "a");
    SerializationNode& bs = node.createChildNode("TypeB");
    for (auto& entry : force.getTypeBs())
        bs.createChildNode("Type").setIntProperty("type", entry.first).setDoubleProperty("b", entry.second);
    serializeExclusions(force, node);
}

void* MDPDForceProxy::deserialize(const SerializationNode& node) const {
    const XmlReader xml(node, "MDPDForce");
    const int version = xml.integer("version");
    if (version != 1)
        throw OpenMM::OpenMMException("MDPDForce: the XML version must be 1, got " + std::to_string(version));
    MDPDForce* force = new MDPDForce(xml.number("defaultA"), xml.number("defaultB"), xml.number("defaultCutoff"), xml.number("densityCutoff"));
    try {
        force->setForceGroup(xml.integer("forceGroup"));
        force->setNonbondedMethod((MDPDForce::NonbondedMethod) xml.integer("method"));
        deserializeTypeTable(xml, *force, "a");
        for (const XmlReader& t : xml.child("TypeB").children())
            force->setTypeB(t.integer("type"), t.number("b"));
        deserializeExclusions(xml, *force);
    }
    catch (...) {
        delete force;
        throw;
    }
    return force;
}
