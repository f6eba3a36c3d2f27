#ifndef OPENMMDPD_COMMONSWEEPDYNAMICS_H_
#define OPENMMDPD_COMMONSWEEPDYNAMICS_H_

#include "openmmdpd/CommonDynamics.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"

namespace DPDPlugin {

/**
 * Velocity Verlet with the conservative force, split with pairwise-sequential sweeps, on
 * the device, step for step as ReferenceSweepDynamics (kernels/sweep.cc).  The carried
 * force is the conservative force FC at the current positions.  A sweep visits the pairs
 * in ReferencePairList's order, on the Reference's grid and not the cell list of the pair
 * forces: in a periodic box n_k = floor(L_k / cutoff) lowered to a multiple of 3, one launch
 * per colour, or one work item for every cell where an axis has fewer than 3 cells; in an
 * open System the bounding box of the particles that move, always coloured.
 */
class CommonSweepDynamics : public CommonDynamics {
protected:
    /** The pair rule of a sweep (kernels/sweep.cc). */
    enum Rule { ShardlowRule = 0, LoweRule = 1, PairOrnsteinUhlenbeckRule = 2 };
    /** ruleSources and withPairForces: a rule's own kernels, and whether it uses pairForces too (CommonDynamics). */
    CommonSweepDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const DPDThermostatIntegrator& integrator,
                        const std::string& platform, const std::vector<std::string>& ruleSources = {}, bool withPairForces = false);
    /** At the start of a step: make sure the carried force is FC at the current positions. */
    void ensureCarriedForce(OpenMM::ContextImpl& context, int forceGroups);
    /** v += dt/2m F ; r += dt v ; F <- FC(r) ; v += dt/2m F. */
    void velocityVerlet(OpenMM::ContextImpl& context, int forceGroups, double dt);
    /** v += kick/m F ; r += drift v (F the carried force), then the sliding boundaries; flags a position that blew up. */
    void kickDrift(double kick, double drift);
    /** F <- FC(r) at the current positions; then v += kick/m F unless kick is 0. */
    void takeConservativeForce(OpenMM::ContextImpl& context, int forceGroups, double kick);
    /**
     * The Context's velocities swept pair by pair at the current positions with a rule over
     * a time h, the numbers of `stream` keyed by step (partner: their partners,
     * PairRandom::partnerGaussian), transverse friction's noise vectors those of
     * transverseStream at the same step; reverse: in exactly the opposite order.  While a
     * thermostat virial is recorded, the sweep adds that of its pair impulses over dt, the
     * step (docs/theory/pressure-tensor.md).
     */
    void sweep(Rule rule, double h, double dt, PairRandom::Stream stream, PairRandom::Stream transverseStream, long long step,
               bool reverse, bool partner = false);

    double constraintTolerance = 1e-5;  // the integrator's, set at each step

private:
    /** The Reference's grid at the current positions, each cell's atoms in index order. */
    void buildGrid();
    /** The constraint clusters of the System for the sweeps' impulses (kernels/pairConstraints.cc). */
    void createConstraintClusters(const OpenMM::System& system);
    CommonCellScan scan;
    static constexpr long long MaxGridCells = 1LL << 27;
    CommonGridBox grid;
    OpenMM::ComputeKernel assignKernel, clearKernel, fillKernel, sortKernel, colourKernel, scatterKernel, kickDriftKernel,
            conservativeKernel;
    OpenMM::ComputeArray position, atomCell, cellCount, cellStart, cellAtoms;
    OpenMM::ComputeKernel factorKernel;
    OpenMM::ComputeArray clusterOfAtom, clusterStart, constraintAtoms, constraintDirection, clusterMatrixStart, clusterMatrix;
    int numClusters = 0;
    int numCells[3] = {0, 0, 0}, totalCells = 0;
    DeviceBox box;  // the box of the last grid (buildGrid)
};

/** Shardlow's S1 and S2 (ShardlowIntegrator) on the device. */
class CommonShardlowDynamics : public CommonSweepDynamics {
public:
    CommonShardlowDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const ShardlowIntegrator& integrator,
                           const std::string& platform) :
            CommonSweepDynamics(cc, system, integrator, platform) {}
    void step(OpenMM::ContextImpl& context, const ShardlowIntegrator& integrator);
};

/** Lowe-Andersen and the pair Ornstein-Uhlenbeck update, both splittings (LoweAndersenIntegrator), on the device. */
class CommonLoweAndersenDynamics : public CommonSweepDynamics {
public:
    CommonLoweAndersenDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const LoweAndersenIntegrator& integrator,
                               const std::string& platform) :
            CommonSweepDynamics(cc, system, integrator, platform) {}
    void step(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator);

private:
    /** B A O A B with the velocities kept at O: v += dt/m F ; r += dt/2 v ; O ; r += dt/2 v ; F <- FC(r). */
    void middleStep(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator);
    /** O: the pair thermostat over dt at the current positions, its numbers keyed by step. */
    void applyThermostat(const LoweAndersenIntegrator& integrator, long long step);
};

} // namespace DPDPlugin

#endif
