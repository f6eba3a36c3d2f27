// The copies of fast forces that the CPU platform's staggered integrator evaluates in a
// Context of the polymer alone (for K > 1).  A force it cannot copy costs speed silently
// (the main Context evaluates the fast groups instead), so what must copy is tested here.
#if OPENMMDPD_HAVE_CPU
#include "openmmdpd/StaggeredDynamics.h"
#include "openmm/Context.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/VerletIntegrator.h"
#include <gtest/gtest.h>
#include <memory>

using namespace DPDPlugin;
using namespace OpenMM;

#if OPENMMDPD_OPENMM_MAJOR >= 8
TEST(StaggeredFastCopy, CustomNonbondedWithComputedValuesIsCopied) {
    // Particles 1, 3, 4 are the polymer (one interaction group among them); 0, 2, 5 solvent.
    // A WCA-like force whose sigma is a computed value (OpenMM >= 8): the copy over the
    // polymer must give the polymer the forces the full System gives it.
    System full;
    std::vector<Vec3> positions;
    for (int i = 0; i < 6; i++) {
        full.addParticle(1.0);
        positions.push_back(Vec3(0.37 * i, 0.05 * (i % 2), 0.02 * i));
    }
    CustomNonbondedForce* wca = new CustomNonbondedForce("4*((s/r)^12-(s/r)^6)+1; s=0.5*(sig1+sig2)");
    wca->addPerParticleParameter("half");
    wca->addComputedValue("sig", "2*half");
    for (int i = 0; i < 6; i++)
        wca->addParticle({0.19 + 0.01 * i});
    wca->setCutoffDistance(1.5);
    wca->addInteractionGroup({1, 3, 4}, {1, 3, 4});
    full.addForce(wca);

    const std::vector<int> index = {-1, 0, -1, 1, 2, -1};
    std::unique_ptr<Force> copy(copyOverPolymer(*wca, index));
    ASSERT_NE(copy, nullptr);
    System polymer;
    for (int k = 0; k < 3; k++)
        polymer.addParticle(1.0);
    polymer.addForce(copy.release());

    Platform& reference = Platform::getPlatformByName("Reference");
    VerletIntegrator i1(0.001), i2(0.001);
    Context fullContext(full, i1, reference), polymerContext(polymer, i2, reference);
    fullContext.setPositions(positions);
    polymerContext.setPositions({positions[1], positions[3], positions[4]});
    const std::vector<Vec3> fullForce = fullContext.getState(State::Forces).getForces();
    const std::vector<Vec3> polymerForce = polymerContext.getState(State::Forces).getForces();
    for (int i = 0; i < 6; i++)
        if (index[i] >= 0) {
            EXPECT_GT(std::sqrt(fullForce[i].dot(fullForce[i])), 1.0) << "particle " << i << " feels the force";
            for (int d = 0; d < 3; d++)
                EXPECT_NEAR(polymerForce[index[i]][d], fullForce[i][d], 1e-10) << "particle " << i;
        }
}
#endif

#endif
