#ifndef OPENMMDPD_DPDSERIALIZATIONHELPERS_H_
#define OPENMMDPD_DPDSERIALIZATIONHELPERS_H_

#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmm/serialization/SerializationNode.h"
#include "openmm/serialization/SerializationProxy.h"

namespace DPDPlugin {

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
