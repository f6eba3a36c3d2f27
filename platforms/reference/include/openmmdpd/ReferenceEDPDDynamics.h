#ifndef OPENMMDPD_REFERENCEEDPDDYNAMICS_H_
#define OPENMMDPD_REFERENCEEDPDDYNAMICS_H_

#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/ReferenceDynamics.h"
#include "openmmdpd/ReferencePairMemory.h"

namespace DPDPlugin {

/**
 * Extended DPD (docs/theory/edpd.md, Cotter and Reich 2003), both schemes: Störmer-Verlet with
 * one force evaluation per step and the pair variables s_k of a ReferencePairMemory.  The
 * carried force is F = FC - sum_k wR e s_k over the pairs in range at the current state.
 */
class ReferenceEDPDDynamics : public ReferenceDynamics {
public:
    ReferenceEDPDDynamics(const OpenMM::System& system, const EDPDIntegrator& integrator) :
            ReferenceDynamics(system, integrator, 1), memory(parameters, random) {}
    void step(OpenMM::ContextImpl& context, const EDPDIntegrator& integrator);
    bool getPairVariable(int i, int j, double& value, long long& step) const;
    long long getNumPairVariables() const { return memory.size(); }

protected:
    void saveExtraState(std::ostream& stream) const override { memory.write(stream); }
    void loadExtraState(CheckpointReader& reader) override { loaded = memory.read(reader); }
    void commitExtraState() override { memory.restore(std::move(loaded)); }
    void resetExtraState() override { memory.clear(); }

private:
    /** The recurrence of the integrator's scheme, alpha and step size. */
    AuxiliaryRecurrence recurrence(const EDPDIntegrator& integrator) const;
    /** F = FC - sum_k wR e s_k over `pairs`, their s taken from the memory. */
    std::vector<OpenMM::Vec3> totalForce(const std::vector<OpenMM::Vec3>& FC, const std::vector<PairGeometry>& pairs,
                                         SymmetricTensor* virial = nullptr) const;
    /** v += dt/(2m) F for every particle. */
    void halfKick(std::vector<OpenMM::Vec3>& v, const std::vector<OpenMM::Vec3>& F, double dt) const;
    ReferencePairMemory memory;
    ReferencePairMemory::Saved loaded;  // read from a checkpoint, until all of it is read
};

} // namespace DPDPlugin

#endif
