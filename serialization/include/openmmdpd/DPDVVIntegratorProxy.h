#ifndef OPENMMDPD_DPDVVINTEGRATORPROXY_H_
#define OPENMMDPD_DPDVVINTEGRATORPROXY_H_

#include "openmm/serialization/SerializationProxy.h"

namespace DPDPlugin {

/** XML serialization of DPDVVIntegrator (every parameter, types and type pairs included). */
class DPDVVIntegratorProxy : public OpenMM::SerializationProxy {
public:
    DPDVVIntegratorProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const override;
    void* deserialize(const OpenMM::SerializationNode& node) const override;
};

} // namespace DPDPlugin

#endif
