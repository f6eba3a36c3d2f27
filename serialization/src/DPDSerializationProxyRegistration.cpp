#include "openmmdpd/DPDSerializationHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"

using namespace DPDPlugin;

// Registered when the library is loaded, so that XmlSerializer knows our classes as soon
// as the plugin (or the Python module) is.
extern "C" void __attribute__((constructor)) registerDPDSerializationProxies() {
    OpenMM::SerializationProxy::registerProxy(typeid(DPDVVIntegrator), new DPDIntegratorProxy<DPDVVIntegrator>());
    OpenMM::SerializationProxy::registerProxy(typeid(ShardlowIntegrator), new DPDIntegratorProxy<ShardlowIntegrator>());
    OpenMM::SerializationProxy::registerProxy(typeid(LoweAndersenIntegrator), new DPDIntegratorProxy<LoweAndersenIntegrator>());
    OpenMM::SerializationProxy::registerProxy(typeid(EDPDIntegrator), new DPDIntegratorProxy<EDPDIntegrator>());
    OpenMM::SerializationProxy::registerProxy(typeid(StaggeredDPDIntegrator), new DPDIntegratorProxy<StaggeredDPDIntegrator>());
    OpenMM::SerializationProxy::registerProxy(typeid(DenOtterClarkeIntegrator), new DPDIntegratorProxy<DenOtterClarkeIntegrator>());
    OpenMM::SerializationProxy::registerProxy(typeid(DPDSoftRepulsionForce), new DPDSoftRepulsionForceProxy());
    OpenMM::SerializationProxy::registerProxy(typeid(MDPDForce), new MDPDForceProxy());
}
