#ifndef OPENMMDPD_COMMONEDPDDYNAMICS_H_
#define OPENMMDPD_COMMONEDPDDYNAMICS_H_

#include "openmmdpd/CommonDynamics.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/PairEvaluators.h"

namespace DPDPlugin {

/**
 * Extended DPD on the device, step for step as ReferenceEDPDDynamics (kernels/edpd.cc),
 * constraints and virtual sites included.  The pair variables live in a table by atom, row a
 * holding the pairs (a, b > a) sorted by b, in range or archived; each step merges it with the
 * pairs in range now into a second table, and the two swap.  A row that outgrows the table's
 * capacity is noticed at once (the step reads one number back), the capacity grows and the
 * merge runs again.  The carried force is FC - sum_k w e s_k.
 */
class CommonEDPDDynamics : public CommonDynamics {
public:
    CommonEDPDDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const EDPDIntegrator& integrator,
                       const std::string& platform);
    void step(OpenMM::ContextImpl& context, const EDPDIntegrator& integrator);
    bool getPairVariable(int i, int j, double& value, long long& step) const;
    long long getNumPairVariables() const;

protected:
    void saveExtraState(std::ostream& stream) const override;
    void loadExtraState(CheckpointReader& reader) override;
    void commitExtraState() override;
    void resetExtraState() override;

private:
    /** One entry of the table on the host: in range (s, w^2), archived (s at a step), or both. */
    struct Entry {
        int partner, flags;
        double value, weight2, archived;
        long long archivedStep;
    };
    /** The table as the host holds it: the entries of each particle's row. */
    typedef std::vector<std::vector<Entry>> Rows;
    /** A table on the device: rows `capacity` entries apart. */
    struct Table {
        OpenMM::ComputeArray partner, flags, value, weight2, archived, archivedStep, count;
    };
    void allocate(Table& table, int capacity);
    /** `array` made to hold `size` elements (its contents are not kept). */
    void sizeArray(OpenMM::ComputeArray& array, int size, int elementSize, const std::string& arrayName);
    Rows download(const Table& table) const;
    void upload(Table& table, const Rows& rows);
    /** Merge the current table with the pairs in range at the current positions into the other (see kernels/edpd.cc). */
    void merge(long long step, bool advance, const AuxiliaryRecurrence& recurrence);
    /** Grow both tables (keeping the current one's entries) to hold rows of `entries`. */
    void grow(int entries);
    /** The variables' pair forces at the current positions, their virial if recorded; carried = FC + them (and v += dt/2m carried if kick). */
    void carryForce(bool kick, double dt, bool virial);
    /** The current table on the host, downloaded once after each change. */
    const Rows& hostRows() const;
    /** The Context's step count was set from outside to `step`: archived steps move with it. */
    void renumberSteps(long long step);

    std::unique_ptr<CommonCellList> pairCells;
    OpenMM::ComputeKernel mergeKernel, forceKernel, carryKernel, renumberKernel, driftKernel;
    OpenMM::ComputeArray auxiliaryForce, candidatePartner, candidateWeight2, needed;
    Table tables[2];
    int current = 0, capacity = 0;
    long long inRangeStep = -1;
    mutable Rows cache;  // see hostRows
    mutable bool cacheValid = false;
    Rows loaded;  // read from a checkpoint, until all of it is read
    long long loadedStep = -1;
};

} // namespace DPDPlugin

#endif
