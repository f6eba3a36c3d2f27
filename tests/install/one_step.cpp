// One Groot-Warren step of a soft fluid through the installed C++ API and kernels.
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmm/Context.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include <cstdio>
#include <vector>

int main() {
    OpenMM::Platform::loadPluginsFromDirectory(OPENMMDPD_PLUGIN_DIR);
    OpenMM::System system;
    const double box = 4.0;
    system.setDefaultPeriodicBoxVectors(OpenMM::Vec3(box, 0, 0), OpenMM::Vec3(0, box, 0), OpenMM::Vec3(0, 0, box));
    std::vector<OpenMM::Vec3> positions;
    for (int i = 0; i < 192; i++) {
        system.addParticle(1.0);
        positions.push_back(OpenMM::Vec3(0.5 * (i % 8), 0.5 * (i / 8 % 8), 0.5 * (i / 64)));
    }
    system.addForce(new DPDPlugin::DPDSoftRepulsionForce(25.0, 1.0));
    DPDPlugin::DPDVVIntegrator integrator(120.27, 4.5, 1.0, 0.02);
    OpenMM::Context context(system, integrator, OpenMM::Platform::getPlatformByName("Reference"));
    context.setPositions(positions);
    integrator.step(1);
    const OpenMM::State state = context.getState(OpenMM::State::Energy);
    std::printf("one GW step: step %lld, potential energy %.6f kJ/mol\n", state.getStepCount(), state.getPotentialEnergy());
    return state.getStepCount() == 1 ? 0 : 1;
}
