#ifndef OPENMMDPD_DPDSERIALIZATIONHELPERS_H_
#define OPENMMDPD_DPDSERIALIZATIONHELPERS_H_

#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmm/serialization/SerializationNode.h"
#include "openmm/serialization/SerializationProxy.h"

namespace DPDPlugin {

/**
 * Particle types and type pairs of a DPD integrator or DPDSoftRepulsionForce (anything
 * with their type-table methods); `valueName` names the pair parameter in the XML.
 */
template <class Owner>
void serializeTypeTable(const Owner& owner, OpenMM::SerializationNode& node, const char* valueName) {
    OpenMM::SerializationNode& types = node.createChildNode("ParticleTypes");
    for (auto& entry : owner.getParticleTypes())
        types.createChildNode("Particle").setIntProperty("index", entry.first).setIntProperty("type", entry.second);
    OpenMM::SerializationNode& pairs = node.createChildNode("TypePairs");
    for (int k = 0; k < owner.getNumTypePairs(); k++) {
        int t1, t2;
        double value, cutoff;
        owner.getTypePairParameters(k, t1, t2, value, cutoff);
        pairs.createChildNode("TypePair").setIntProperty("type1", t1).setIntProperty("type2", t2)
                .setDoubleProperty(valueName, value).setDoubleProperty("cutoff", cutoff);
    }
}

template <class Owner>
void deserializeTypeTable(const OpenMM::SerializationNode& node, Owner& owner, const char* valueName) {
    for (const OpenMM::SerializationNode& p : node.getChildNode("ParticleTypes").getChildren())
        owner.setParticleType(p.getIntProperty("index"), p.getIntProperty("type"));
    for (const OpenMM::SerializationNode& p : node.getChildNode("TypePairs").getChildren())
        owner.addTypePair(p.getIntProperty("type1"), p.getIntProperty("type2"), p.getDoubleProperty(valueName),
                          p.getDoubleProperty("cutoff"));
}

/** The parameters every DPDThermostatIntegrator has, written into a proxy's node. */
void serializeThermostatParameters(const DPDThermostatIntegrator& integrator, OpenMM::SerializationNode& node);
/** Read them back (the constructor's arguments are read by each proxy). */
void deserializeThermostatParameters(const OpenMM::SerializationNode& node, DPDThermostatIntegrator& integrator);

/**
 * XML serialization of a DPD integrator class: the shared parameters plus what
 * Traits<Integrator> adds (see DPDIntegratorProxies.cpp).
 */
template <class Integrator>
class DPDIntegratorProxy : public OpenMM::SerializationProxy {
public:
    DPDIntegratorProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const override;
    void* deserialize(const OpenMM::SerializationNode& node) const override;
};

/** XML serialization of DPDSoftRepulsionForce (types, type pairs and exclusions included). */
class DPDSoftRepulsionForceProxy : public OpenMM::SerializationProxy {
public:
    DPDSoftRepulsionForceProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const override;
    void* deserialize(const OpenMM::SerializationNode& node) const override;
};

} // namespace DPDPlugin

#endif
