#ifndef OPENMMDPD_POLYMERFORCECONTEXT_H_
#define OPENMMDPD_POLYMERFORCECONTEXT_H_

#include "openmmdpd/PolymerSelection.h"
#include "openmm/Context.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/Platform.h"
#include "openmm/System.h"
#include "openmm/VerletIntegrator.h"
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * A copy of `force` over the polymer particles only (particle i becomes index[i], -1 for a
 * particle outside the polymer), for the Context of the polymer alone; null when the force
 * touches a particle outside the polymer or cannot be copied faithfully.
 */
OpenMM::Force* copyOverPolymer(const OpenMM::Force& force, const std::vector<int>& index);

/**
 * Copy the box (when it differs from cachedBox, which is then updated) and the values of the
 * global parameters `target` has to a Context beside the main one.
 */
void syncBoxAndParameters(OpenMM::Context& target, const OpenMM::Vec3* box, const std::map<std::string, double>& parameters,
                          OpenMM::Vec3* cachedBox);

/**
 * The fast forces of a staggered System on its polymer particles alone, evaluated by OpenMM
 * from copies of the user's Force objects in a Context holding only the polymer, so that a
 * sub-step costs what the fast forces on the polymer cost.
 *
 * A small polymer (PAIR_CANDIDATE_LIMIT) is evaluated on the Reference platform: it has no
 * thread pool to wake, and it evaluates a few hundred terms in microseconds.  Its
 * CustomNonbondedForce kernel, though, builds a neighbour list over the whole box and
 * recompiles the energy expression at every call, so a CustomNonbondedForce is evaluated
 * there as a CustomBondForce of the same energy, cut off at the same distance, over the
 * pairs of its interaction groups that a Verlet list (cutoff + skin, rebuilt when the polymer
 * or the box has moved by part of the skin) finds.  Each listed pair has its own two slot
 * particles, so the list changes without changing a bond's particles, and a pair's force
 * does not depend on which other pairs are listed: the same sums in the same order whenever
 * the list was built.  A larger polymer is evaluated on the main Context's platform, with
 * the CustomNonbondedForce copied as it is.
 */
class PolymerForceContext {
public:
    /**
     * Null if a force of the fast groups cannot be evaluated over the polymer alone (see
     * copyOverPolymer): the caller's Context then evaluates the fast groups itself.
     * `platform` and `properties` are those of the main Context.
     */
    static std::unique_ptr<PolymerForceContext> create(const OpenMM::System& system, int fastGroups, const PolymerSelection& polymer,
                                                       OpenMM::Platform& platform,
                                                       const std::map<std::string, std::string>& properties);
    /**
     * fast[k] <- the fast force on polymer particle k (particles[k]) at the System's
     * positions r, in the box `box`, with the global parameter values `parameters`.
     */
    void compute(const std::vector<OpenMM::Vec3>& r, const OpenMM::Vec3* box, const std::map<std::string, double>& parameters,
                 std::vector<OpenMM::Vec3>& fast);
    /** Whether CustomNonbondedForces are evaluated as listed pairs on the Reference platform. */
    bool evaluatesListedPairs() const { return !tables.empty(); }
    /** Most interaction-group pairs of a polymer evaluated as listed pairs (the list is rebuilt by going over all of them). */
    static const size_t PAIR_CANDIDATE_LIMIT = 100000;
    /** The Verlet list's skin, a fraction of the cutoff: more pairs evaluated against fewer rebuilds. */
    static constexpr double LIST_SKIN = 0.25;

private:
    /** A CustomNonbondedForce over the polymer as a CustomBondForce over listed pairs. */
    struct PairTable {
        const OpenMM::CustomNonbondedForce* force;   // the user's
        double cutoff, skin;                         // skin 0: every candidate is listed
        bool periodic;
        std::vector<std::pair<int, int>> candidates;  // polymer indices, in OpenMM's order within a pair
        std::vector<std::vector<double>> parameters;  // per-particle parameters, by polymer index
        std::vector<int> listed;                      // the candidates within cutoff + skin at the last build
        int firstSlot = 0, capacity = 0;
        OpenMM::CustomBondForce* bonds = nullptr;     // in the side System
    };
    PolymerForceContext(const OpenMM::System& system, int fastGroups, const PolymerSelection& polymer) :
            system(system), fastGroups(fastGroups), particles(polymer.particles), index(polymer.index) {}
    /** A pair table for each CustomNonbondedForce in a fast group; false if the polymer is not small or one cannot be listed. */
    bool makePairTables();
    /** A pair table for `force`, of at most `limit` candidates; false if it cannot be listed faithfully. */
    bool addPairTable(const OpenMM::CustomNonbondedForce& force, size_t limit);
    static std::vector<double> slotParameters(const PairTable& table, int s);
    /** The CustomBondForce of a table's slots, its bonds at the parameters of the listed pairs. */
    static OpenMM::CustomBondForce* slotBonds(const PairTable& table);
    /** The side System and Context for the current capacities; false if a force cannot be copied. */
    bool makeContext();
    void parkSlots();
    /** Whether a pair may have come within the cutoff since the last listing. */
    bool needsNewList(const OpenMM::Vec3* box) const;
    /** Lists the pairs within cutoff + skin again; false if a table outgrew its slots. */
    bool listPairs(const OpenMM::Vec3* box);
    /** listPairs(), then the slot bonds' parameters, or a larger side Context. */
    void listPairsAgain(const OpenMM::Vec3* box);

    const OpenMM::System& system;
    const int fastGroups;
    const std::vector<int> particles, index;
    std::vector<PairTable> tables;
    OpenMM::Platform* platform = nullptr;
    std::map<std::string, std::string> properties;
    std::vector<OpenMM::Vec3> polymerPositions, sidePositions, listPositions;
    OpenMM::Vec3 listBox[3], sideBox[3];
    std::unique_ptr<OpenMM::System> sideSystem;
    std::unique_ptr<OpenMM::VerletIntegrator> sideIntegrator;
    std::unique_ptr<OpenMM::Context> sideContext;
};

} // namespace DPDPlugin

#endif
