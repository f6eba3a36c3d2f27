#ifndef OPENMMDPD_EDPDDYNAMICS_H_
#define OPENMMDPD_EDPDDYNAMICS_H_

#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/PairDynamics.h"
#include "openmmdpd/PairMemory.h"

namespace DPDPlugin {

/**
 * Extended DPD (docs/theory/edpd.md): Störmer-Verlet with the pair variables s_k of a
 * PairMemory.  The carried force is FC - sum_k wR e s_k at the current state.
 */
class EDPDDynamics : public PairDynamics {
public:
    EDPDDynamics(const OpenMM::System& system, const EDPDIntegrator& integrator, ParallelExecutor& executor);
    void step(OpenMM::ContextImpl& context, const EDPDIntegrator& integrator);
    const PairMemory& getMemory() const { return memory; }

protected:
    void saveExtraState(std::ostream& stream) const override { memory.write(stream); }
    void loadExtraState(CheckpointReader& reader) override { loaded = memory.read(reader); }
    void commitExtraState() override { memory.restore(std::move(loaded)); }
    void resetExtraState() override { memory.clear(); }

private:
    /** auxiliary <- -sum_k wR e s_k over the pairs in range, from pairS. */
    void computeAuxiliaryForce();
    PairMemory memory;
    PairMemory::Saved loaded;  // read from a checkpoint, until all of it is read
    std::vector<double> pairS, coefficient;
    std::vector<OpenMM::Vec3> auxiliary;
};

} // namespace DPDPlugin

#endif
