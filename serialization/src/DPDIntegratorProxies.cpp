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
    static void read(const XmlReader& xml, DPDVVIntegrator& integrator) {
        integrator.setVariant((DPDVVIntegrator::Variant) xml.integer("variant"));
        integrator.setLambda(xml.number("lambda"));
        integrator.setMaxIterations(xml.integer("maxIterations"));
        integrator.setTolerance(xml.number("tolerance"));
    }
};

template <>
struct Traits<ShardlowIntegrator> {
    static void write(const ShardlowIntegrator& integrator, SerializationNode& node) {
        node.setIntProperty("order", integrator.getOrder());
    }
    static void read(const XmlReader& xml, ShardlowIntegrator& integrator) {
        integrator.setOrder(xml.integer("order"));
    }
};

template <>
struct Traits<LoweAndersenIntegrator> {
    static void write(const LoweAndersenIntegrator& integrator, SerializationNode& node) {
        node.setIntProperty("method", integrator.getMethod());
        node.setIntProperty("splitting", integrator.getSplitting());
    }
    static void read(const XmlReader& xml, LoweAndersenIntegrator& integrator) {
        integrator.setMethod((LoweAndersenIntegrator::Method) xml.integer("method"));
        // Files written before the splitting existed hold the AfterVerlet scheme.
        integrator.setSplitting((LoweAndersenIntegrator::Splitting) xml.integer("splitting", LoweAndersenIntegrator::AfterVerlet));
    }
};

template <>
struct Traits<EDPDIntegrator> {
    static void write(const EDPDIntegrator& integrator, SerializationNode& node) {
        node.setDoubleProperty("alpha", integrator.getAlpha());
        node.setIntProperty("scheme", integrator.getScheme());
    }
    static void read(const XmlReader& xml, EDPDIntegrator& integrator) {
        integrator.setScheme((EDPDIntegrator::Scheme) xml.integer("scheme"));
    }
};

template <>
struct Traits<DenOtterClarkeIntegrator> {
    static void write(const DenOtterClarkeIntegrator& integrator, SerializationNode& node) {
        node.setDoubleProperty("averageFDDotV", integrator.getAverageFDDotV());
        node.setDoubleProperty("averageFDDotFD", integrator.getAverageFDDotFD());
        node.setDoubleProperty("averageFRDotFR", integrator.getAverageFRDotFR());
    }
    static void read(const XmlReader& xml, DenOtterClarkeIntegrator& integrator) {
        // 0 is "not set", which the setters do not take.
        const double fdDotV = xml.number("averageFDDotV"), fdDotFD = xml.number("averageFDDotFD"),
                     frDotFR = xml.number("averageFRDotFR");
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
Integrator* construct(const XmlReader& xml) {
    return new Integrator(xml.number("temperature"), xml.number("defaultFriction"),
                          xml.number("defaultCutoff"), xml.number("stepSize"));
}

template <>
EDPDIntegrator* construct<EDPDIntegrator>(const XmlReader& xml) {
    return new EDPDIntegrator(xml.number("temperature"), xml.number("defaultFriction"),
                              xml.number("defaultCutoff"), xml.number("alpha"),
                              xml.number("stepSize"));
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
    static void read(const XmlReader& xml, StaggeredDPDIntegrator& integrator) {
        integrator.setBaseScheme((StaggeredDPDIntegrator::BaseScheme) xml.integer("baseScheme"));
        integrator.setNumSubSteps(xml.integer("numSubSteps"));
        integrator.setLambda(xml.number("lambda"));
        integrator.setRelaxationParameters(xml.number("mu"), xml.number("a"), xml.number("b"));
        integrator.setWeighted(xml.flag("weighted"));
        integrator.setFastForceGroups(xml.integer("fastForceGroups"));
        std::vector<int> particles;
        for (const XmlReader& particle : xml.child("PolymerParticles").children())
            particles.push_back(particle.integer("index"));
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
    const XmlReader xml(node, proxyName((Integrator*) nullptr));
    const int version = xml.integer("version");
    if (version != 1)
        throw OpenMM::OpenMMException(std::string(proxyName((Integrator*) nullptr)) + ": the XML version must be 1, got " +
                                      std::to_string(version));
    Integrator* integrator = construct<Integrator>(xml);
    try {
        deserializeThermostatParameters(xml, *integrator);
        Traits<Integrator>::read(xml, *integrator);
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
