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

/**
 * The attributes of one XML node, read strictly: a required attribute that is missing, or any
 * attribute whose text is not a number of the asked kind (OpenMM's own getters read such text
 * as 0), is refused with "<owner>: cannot read the XML: ..." naming the node and attribute.
 */
class XmlReader {
public:
    XmlReader(const OpenMM::SerializationNode& node, std::string owner) : node(node), owner(std::move(owner)) {}
    double number(const char* name) const;
    double number(const char* name, double defaultValue) const;
    int integer(const char* name) const;
    int integer(const char* name, int defaultValue) const;
    bool flag(const char* name) const;
    bool flag(const char* name, bool defaultValue) const;
    /** The child node of that name, read with the same owner. */
    XmlReader child(const char* name) const;
    /** Whether there is a child node of that name. */
    bool hasChild(const char* name) const;
    /** Every child node, in order. */
    std::vector<XmlReader> children() const;

private:
    const std::string& text(const char* name) const;
    [[noreturn]] void refuse(const char* name, const std::string& why) const;
    const OpenMM::SerializationNode& node;
    std::string owner;
};

template <class Owner>
void deserializeTypeTable(const XmlReader& xml, Owner& owner, const char* valueName) {
    for (const XmlReader& p : xml.child("ParticleTypes").children())
        owner.setParticleType(p.integer("index"), p.integer("type"));
    for (const XmlReader& p : xml.child("TypePairs").children())
        owner.addTypePair(p.integer("type1"), p.integer("type2"), p.number(valueName), p.number("cutoff"));
}

/** A force's exclusions (getNumExclusions, getExclusionParticles) as an Exclusions child of node. */
template <class Force>
void serializeExclusions(const Force& force, OpenMM::SerializationNode& node) {
    OpenMM::SerializationNode& exclusions = node.createChildNode("Exclusions");
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        exclusions.createChildNode("Exclusion").setIntProperty("p1", p1).setIntProperty("p2", p2);
    }
}

/** The exclusions serializeExclusions wrote, added to force. */
template <class Force>
void deserializeExclusions(const XmlReader& xml, Force& force) {
    for (const XmlReader& e : xml.child("Exclusions").children())
        force.addExclusion(e.integer("p1"), e.integer("p2"));
}

/** The parameters every DPDThermostatIntegrator has, written into a proxy's node. */
void serializeThermostatParameters(const DPDThermostatIntegrator& integrator, OpenMM::SerializationNode& node);
/** Read them back (the constructor's arguments are read by each proxy). */
void deserializeThermostatParameters(const XmlReader& xml, DPDThermostatIntegrator& integrator);

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

/** XML serialization of MDPDForce (types, type pairs, per-type B and exclusions included). */
class MDPDForceProxy : public OpenMM::SerializationProxy {
public:
    MDPDForceProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const override;
    void* deserialize(const OpenMM::SerializationNode& node) const override;
};

} // namespace DPDPlugin

#endif
