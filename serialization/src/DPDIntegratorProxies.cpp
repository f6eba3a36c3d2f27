#include "openmmdpd/DPDSerializationHelpers.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/OpenMMException.h"

using namespace DPDPlugin;
using OpenMM::SerializationNode;

namespace {

// What each class adds to the shared parameters.
template <class Integrator>
struct Traits;

template <>
struct Traits<DPDVVIntegrator> {
    static void write(const DPDVVIntegrator& integrator, SerializationNode& node) {
        node.setIntProperty("variant", integrator.getVariant());
        node.setDoubleProperty("lambda", integrator.getLambda());
        node.setIntProperty("maxIterations", integrator.getMaxIterations());
        node.setDoubleProperty("tolerance", integrator.getTolerance());
    }
    static void read(const SerializationNode& node, DPDVVIntegrator& integrator) {
        integrator.setVariant((DPDVVIntegrator::Variant) node.getIntProperty("variant"));
        integrator.setLambda(node.getDoubleProperty("lambda"));
        integrator.setMaxIterations(node.getIntProperty("maxIterations"));
        integrator.setTolerance(node.getDoubleProperty("tolerance"));
    }
};

template <>
struct Traits<ShardlowIntegrator> {
    static void write(const ShardlowIntegrator& integrator, SerializationNode& node) {
        node.setIntProperty("order", integrator.getOrder());
    }
    static void read(const SerializationNode& node, ShardlowIntegrator& integrator) {
        integrator.setOrder(node.getIntProperty("order"));
    }
};

template <>
struct Traits<LoweAndersenIntegrator> {
    static void write(const LoweAndersenIntegrator& integrator, SerializationNode& node) {
        node.setIntProperty("method", integrator.getMethod());
        node.setIntProperty("splitting", integrator.getSplitting());
    }
    static void read(const SerializationNode& node, LoweAndersenIntegrator& integrator) {
        integrator.setMethod((LoweAndersenIntegrator::Method) node.getIntProperty("method"));
        // Files written before the splitting existed hold the AfterVerlet scheme.
        integrator.setSplitting((LoweAndersenIntegrator::Splitting) node.getIntProperty("splitting", LoweAndersenIntegrator::AfterVerlet));
    }
};

template <>
struct Traits<EDPDIntegrator> {
    static void write(const EDPDIntegrator& integrator, SerializationNode& node) {
        node.setDoubleProperty("alpha", integrator.getAlpha());
        node.setIntProperty("scheme", integrator.getScheme());
    }
    static void read(const SerializationNode& node, EDPDIntegrator& integrator) {
        integrator.setScheme((EDPDIntegrator::Scheme) node.getIntProperty("scheme"));
    }
};

template <>
struct Traits<DenOtterClarkeIntegrator> {
    static void write(const DenOtterClarkeIntegrator& integrator, SerializationNode& node) {
        node.setDoubleProperty("averageFDDotV", integrator.getAverageFDDotV());
        node.setDoubleProperty("averageFDDotFD", integrator.getAverageFDDotFD());
        node.setDoubleProperty("averageFRDotFR", integrator.getAverageFRDotFR());
    }
    static void read(const SerializationNode& node, DenOtterClarkeIntegrator& integrator) {
        // 0 is "not set", which the setters do not take.
        const double fdDotV = node.getDoubleProperty("averageFDDotV"), fdDotFD = node.getDoubleProperty("averageFDDotFD"),
                     frDotFR = node.getDoubleProperty("averageFRDotFR");
        if (fdDotV != 0)
            integrator.setAverageFDDotV(fdDotV);
        if (fdDotFD != 0)
            integrator.setAverageFDDotFD(fdDotFD);
        if (frDotFR != 0)
            integrator.setAverageFRDotFR(frDotFR);
    }
};

// The constructor's arguments, as the XML has them.
template <class Integrator>
Integrator* construct(const SerializationNode& node) {
    return new Integrator(node.getDoubleProperty("temperature"), node.getDoubleProperty("defaultFriction"),
                          node.getDoubleProperty("defaultCutoff"), node.getDoubleProperty("stepSize"));
}

template <>
EDPDIntegrator* construct<EDPDIntegrator>(const SerializationNode& node) {
    return new EDPDIntegrator(node.getDoubleProperty("temperature"), node.getDoubleProperty("defaultFriction"),
                              node.getDoubleProperty("defaultCutoff"), node.getDoubleProperty("alpha"),
                              node.getDoubleProperty("stepSize"));
}

template <>
struct Traits<StaggeredDPDIntegrator> {
    static void write(const StaggeredDPDIntegrator& integrator, SerializationNode& node) {
        node.setIntProperty("baseScheme", integrator.getBaseScheme());
        node.setIntProperty("numSubSteps", integrator.getNumSubSteps());
        node.setDoubleProperty("lambda", integrator.getLambda());
        node.setDoubleProperty("mu", integrator.getMu());
        node.setDoubleProperty("a", integrator.getA());
        node.setDoubleProperty("b", integrator.getB());
        node.setBoolProperty("weighted", integrator.getWeighted());
        node.setIntProperty("fastForceGroups", integrator.getFastForceGroups());
        SerializationNode& particles = node.createChildNode("PolymerParticles");
        for (int p : integrator.getPolymerParticles())
            particles.createChildNode("Particle").setIntProperty("index", p);
    }
    static void read(const SerializationNode& node, StaggeredDPDIntegrator& integrator) {
        integrator.setBaseScheme((StaggeredDPDIntegrator::BaseScheme) node.getIntProperty("baseScheme"));
        integrator.setNumSubSteps(node.getIntProperty("numSubSteps"));
        integrator.setLambda(node.getDoubleProperty("lambda"));
        integrator.setRelaxationParameters(node.getDoubleProperty("mu"), node.getDoubleProperty("a"), node.getDoubleProperty("b"));
        integrator.setWeighted(node.getBoolProperty("weighted"));
        integrator.setFastForceGroups(node.getIntProperty("fastForceGroups"));
        std::vector<int> particles;
        for (const SerializationNode& particle : node.getChildNode("PolymerParticles").getChildren())
            particles.push_back(particle.getIntProperty("index"));
        integrator.setPolymerParticles(particles);
    }
};

const char* proxyName(const DPDVVIntegrator*) { return "DPDVVIntegrator"; }
const char* proxyName(const DenOtterClarkeIntegrator*) { return "DenOtterClarkeIntegrator"; }
const char* proxyName(const EDPDIntegrator*) { return "EDPDIntegrator"; }
const char* proxyName(const ShardlowIntegrator*) { return "ShardlowIntegrator"; }
const char* proxyName(const LoweAndersenIntegrator*) { return "LoweAndersenIntegrator"; }
const char* proxyName(const StaggeredDPDIntegrator*) { return "StaggeredDPDIntegrator"; }

} // namespace

template <class Integrator>
DPDIntegratorProxy<Integrator>::DPDIntegratorProxy() : OpenMM::SerializationProxy(proxyName((Integrator*) nullptr)) {
}

template <class Integrator>
void DPDIntegratorProxy<Integrator>::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", 1);
    const Integrator& integrator = *reinterpret_cast<const Integrator*>(object);
    serializeThermostatParameters(integrator, node);
    Traits<Integrator>::write(integrator, node);
}

template <class Integrator>
void* DPDIntegratorProxy<Integrator>::deserialize(const SerializationNode& node) const {
    const int version = node.getIntProperty("version");
    if (version != 1)
        throw OpenMM::OpenMMException(std::string(proxyName((Integrator*) nullptr)) + ": the XML version must be 1, got " +
                                      std::to_string(version));
    Integrator* integrator = construct<Integrator>(node);
    try {
        deserializeThermostatParameters(node, *integrator);
        Traits<Integrator>::read(node, *integrator);
    }
    catch (...) {
        delete integrator;
        throw;
    }
    return integrator;
}

template class DPDPlugin::DPDIntegratorProxy<DPDVVIntegrator>;
template class DPDPlugin::DPDIntegratorProxy<ShardlowIntegrator>;
template class DPDPlugin::DPDIntegratorProxy<LoweAndersenIntegrator>;
template class DPDPlugin::DPDIntegratorProxy<EDPDIntegrator>;
template class DPDPlugin::DPDIntegratorProxy<StaggeredDPDIntegrator>;
template class DPDPlugin::DPDIntegratorProxy<DenOtterClarkeIntegrator>;
