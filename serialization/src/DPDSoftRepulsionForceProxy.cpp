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
    serializeExclusions(force, node);
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
        deserializeExclusions(xml, *force);
    }
    catch (...) {
        delete force;
        throw;
    }
    return force;
}
