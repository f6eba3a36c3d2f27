#include "openmmdpd/DPDVVIntegratorProxy.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmm/OpenMMException.h"
#include "openmm/serialization/SerializationNode.h"

using namespace DPDPlugin;
using namespace OpenMM;

DPDVVIntegratorProxy::DPDVVIntegratorProxy() : SerializationProxy("DPDVVIntegrator") {
}

void DPDVVIntegratorProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", 1);
    const DPDVVIntegrator& integrator = *reinterpret_cast<const DPDVVIntegrator*>(object);
    node.setDoubleProperty("stepSize", integrator.getStepSize());
    node.setDoubleProperty("temperature", integrator.getTemperature());
    node.setDoubleProperty("defaultFriction", integrator.getDefaultFriction());
    node.setDoubleProperty("defaultCutoff", integrator.getDefaultCutoff());
    node.setIntProperty("randomSeed", integrator.getRandomNumberSeed());
    node.setIntProperty("integrationForceGroups", integrator.getIntegrationForceGroups());
    node.setIntProperty("variant", integrator.getVariant());
    node.setDoubleProperty("lambda", integrator.getLambda());
    node.setIntProperty("maxIterations", integrator.getMaxIterations());
    node.setDoubleProperty("tolerance", integrator.getTolerance());
    SerializationNode& types = node.createChildNode("ParticleTypes");
    for (auto& entry : integrator.getParticleTypes())
        types.createChildNode("Particle").setIntProperty("index", entry.first).setIntProperty("type", entry.second);
    SerializationNode& pairs = node.createChildNode("TypePairs");
    for (int k = 0; k < integrator.getNumTypePairs(); k++) {
        int t1, t2;
        double friction, cutoff;
        integrator.getTypePairParameters(k, t1, t2, friction, cutoff);
        pairs.createChildNode("TypePair").setIntProperty("type1", t1).setIntProperty("type2", t2)
                .setDoubleProperty("friction", friction).setDoubleProperty("cutoff", cutoff);
    }
}

void* DPDVVIntegratorProxy::deserialize(const SerializationNode& node) const {
    if (node.getIntProperty("version") != 1)
        throw OpenMMException("Unsupported version number for DPDVVIntegrator");
    DPDVVIntegrator* integrator = new DPDVVIntegrator(node.getDoubleProperty("temperature"), node.getDoubleProperty("defaultFriction"),
                                                      node.getDoubleProperty("defaultCutoff"), node.getDoubleProperty("stepSize"));
    try {
        integrator->setRandomNumberSeed(node.getIntProperty("randomSeed"));
        integrator->setIntegrationForceGroups(node.getIntProperty("integrationForceGroups"));
        integrator->setVariant((DPDVVIntegrator::Variant) node.getIntProperty("variant"));
        integrator->setLambda(node.getDoubleProperty("lambda"));
        integrator->setMaxIterations(node.getIntProperty("maxIterations"));
        integrator->setTolerance(node.getDoubleProperty("tolerance"));
        for (const SerializationNode& p : node.getChildNode("ParticleTypes").getChildren())
            integrator->setParticleType(p.getIntProperty("index"), p.getIntProperty("type"));
        for (const SerializationNode& p : node.getChildNode("TypePairs").getChildren())
            integrator->addTypePair(p.getIntProperty("type1"), p.getIntProperty("type2"), p.getDoubleProperty("friction"),
                                    p.getDoubleProperty("cutoff"));
    }
    catch (...) {
        delete integrator;
        throw;
    }
    return integrator;
}
