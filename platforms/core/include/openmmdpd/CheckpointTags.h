#ifndef OPENMMDPD_CHECKPOINTTAGS_H_
#define OPENMMDPD_CHECKPOINTTAGS_H_

#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <string>

namespace DPDPlugin {

/*
 * The integrator tag of a checkpoint: the class and the variant of its update rule.  A
 * checkpoint continues only the run that wrote it: what the step kernel carries (the force
 * at the current state, pair variables) means something different in every variant.
 */

inline std::string checkpointTag(const DPDVVIntegrator& integrator) {
    const char* variants[] = {"GrootWarren", "DPDVV", "SelfConsistent"};
    return std::string("DPDVVIntegrator (") + variants[integrator.getVariant()] + ")";
}

inline std::string checkpointTag(const DenOtterClarkeIntegrator&) {
    return "DenOtterClarkeIntegrator";
}

inline std::string checkpointTag(const ShardlowIntegrator& integrator) {
    return "ShardlowIntegrator (order " + std::to_string(integrator.getOrder()) + ")";
}

inline std::string checkpointTag(const LoweAndersenIntegrator& integrator) {
    const std::string method = (integrator.getMethod() == LoweAndersenIntegrator::Lowe ? "Lowe" : "PairOrnsteinUhlenbeck");
    return "LoweAndersenIntegrator (" + method + (integrator.getSplitting() == LoweAndersenIntegrator::Middle ? ", Middle)" : ")");
}

inline std::string checkpointTag(const EDPDIntegrator& integrator) {
    return integrator.getScheme() == EDPDIntegrator::OneSided ? "EDPDIntegrator (OneSided)" : "EDPDIntegrator (Symmetric)";
}

inline std::string checkpointTag(const StaggeredDPDIntegrator& integrator) {
    return integrator.getBaseScheme() == StaggeredDPDIntegrator::VelocityVerlet ? "StaggeredDPDIntegrator (VelocityVerlet)"
                                                                                : "StaggeredDPDIntegrator (LoweAndersen)";
}

} // namespace DPDPlugin

#endif
