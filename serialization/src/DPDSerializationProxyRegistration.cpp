#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DPDVVIntegratorProxy.h"
#include "openmm/serialization/SerializationProxy.h"

// Registered when the library is loaded, so that XmlSerializer knows our classes as soon
// as the plugin (or the Python module) is.
extern "C" void __attribute__((constructor)) registerDPDSerializationProxies() {
    OpenMM::SerializationProxy::registerProxy(typeid(DPDPlugin::DPDVVIntegrator), new DPDPlugin::DPDVVIntegratorProxy());
}
