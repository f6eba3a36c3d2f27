#include "openmmdpd/Checkpoints.h"
#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/OpenMMException.h"
#include <sstream>

void DPDPlugin::loadCheckpoint(OpenMM::Context& context, std::istream& stream) {
    // A checkpoint of the Context as it is: OpenMM's own format, so it restores exactly.
    std::stringstream before;
    context.createCheckpoint(before);
    std::stringstream checkpoint;
    checkpoint << stream.rdbuf();
    try {
        if (auto* ours = dynamic_cast<const DPDThermostatIntegrator*>(&context.getIntegrator()))
            requireIntactCheckpoint(checkpoint.str(), ours->className());
        context.loadCheckpoint(checkpoint);
    }
    catch (const std::exception& refused) {
        before.seekg(0);
        context.loadCheckpoint(before);
        std::string why = printable(refused.what());
        throw OpenMM::OpenMMException(why.empty() ? "the checkpoint was refused, with no reason given" : why);
    }
}
