#include "openmmdpd/PolymerForceContext.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/State.h"
#include "openmm/serialization/XmlSerializer.h"
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

// Copies of the fast forces over the polymer particles only (particle i becomes index[i],
// -1 for a particle outside the polymer), for the Context of the polymer alone: each returns
// null when the force touches a particle outside the polymer or cannot be copied faithfully.

OpenMM::Force* copyHarmonicBonds(const OpenMM::HarmonicBondForce& bond, const std::vector<int>& index) {
    std::unique_ptr<OpenMM::HarmonicBondForce> copy(new OpenMM::HarmonicBondForce());
    for (int k = 0; k < bond.getNumBonds(); k++) {
        int i, j;
        double length, kb;
        bond.getBondParameters(k, i, j, length, kb);
        if (index[i] < 0 || index[j] < 0)
            return nullptr;
        copy->addBond(index[i], index[j], length, kb);
    }
    copy->setUsesPeriodicBoundaryConditions(bond.usesPeriodicBoundaryConditions());
    return copy.release();
}

OpenMM::Force* copyCustomBonds(const OpenMM::CustomBondForce& bond, const std::vector<int>& index) {
    if (bond.getNumEnergyParameterDerivatives() > 0)
        return nullptr;
    std::unique_ptr<OpenMM::CustomBondForce> copy(new OpenMM::CustomBondForce(bond.getEnergyFunction()));
    for (int p = 0; p < bond.getNumPerBondParameters(); p++)
        copy->addPerBondParameter(bond.getPerBondParameterName(p));
    for (int p = 0; p < bond.getNumGlobalParameters(); p++)
        copy->addGlobalParameter(bond.getGlobalParameterName(p), bond.getGlobalParameterDefaultValue(p));
    std::vector<double> parameters;
    for (int k = 0; k < bond.getNumBonds(); k++) {
        int i, j;
        bond.getBondParameters(k, i, j, parameters);
        if (index[i] < 0 || index[j] < 0)
            return nullptr;
        copy->addBond(index[i], index[j], parameters);
    }
    copy->setUsesPeriodicBoundaryConditions(bond.usesPeriodicBoundaryConditions());
    return copy.release();
}

/** A CustomNonbondedForce with the energy, parameters, functions and settings of `force`, and no particles. */
OpenMM::CustomNonbondedForce* emptyNonbondedLike(const OpenMM::CustomNonbondedForce& force) {
    std::unique_ptr<OpenMM::CustomNonbondedForce> copy(new OpenMM::CustomNonbondedForce(force.getEnergyFunction()));
    for (int p = 0; p < force.getNumPerParticleParameters(); p++)
        copy->addPerParticleParameter(force.getPerParticleParameterName(p));
    for (int p = 0; p < force.getNumGlobalParameters(); p++)
        copy->addGlobalParameter(force.getGlobalParameterName(p), force.getGlobalParameterDefaultValue(p));
    for (int f = 0; f < force.getNumTabulatedFunctions(); f++)
        copy->addTabulatedFunction(force.getTabulatedFunctionName(f),
                                   OpenMM::XmlSerializer::clone<OpenMM::TabulatedFunction>(force.getTabulatedFunction(f)));
    copy->setNonbondedMethod(force.getNonbondedMethod());
    copy->setCutoffDistance(force.getCutoffDistance());
    copy->setUseSwitchingFunction(force.getUseSwitchingFunction());
    copy->setSwitchingDistance(force.getSwitchingDistance());
#if OPENMMDPD_OPENMM_MAJOR >= 8
    // Per-particle values computed from the parameters (OpenMM 8): without them the copy's
    // energy names unknown variables and the polymer Context could not be made.
    for (int v = 0; v < force.getNumComputedValues(); v++) {
        std::string name, expression;
        force.getComputedValueParameters(v, name, expression);
        copy->addComputedValue(name, expression);
    }
#endif
    return copy.release();
}

/** The particles (in polymer order: index[particles[k]] == k) and the exclusions within the polymer. */
void copyNonbondedParticles(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index,
                            OpenMM::CustomNonbondedForce& copy) {
    std::vector<double> parameters;
    for (size_t i = 0; i < index.size(); i++)
        if (index[i] >= 0) {
            force.getParticleParameters((int) i, parameters);
            copy.addParticle(parameters);
        }
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int i, j;
        force.getExclusionParticles(k, i, j);
        if (index[i] >= 0 && index[j] >= 0)
            copy.addExclusion(index[i], index[j]);
    }
}

/** Whether the force's one interaction group is every polymer particle with every other. */
bool isWholePolymerGroup(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index, size_t numPolymer) {
    if (force.getNumInteractionGroups() != 1)
        return false;
    std::set<int> set1, set2;
    force.getInteractionGroupParameters(0, set1, set2);
    return set1 == set2 && set1.size() == numPolymer && std::all_of(set1.begin(), set1.end(), [&](int i) { return index[i] >= 0; });
}

/** set, renumbered by index; false if a particle is outside the polymer. */
bool mapToPolymer(const std::set<int>& set, const std::vector<int>& index, std::set<int>& mapped) {
    for (int i : set) {
        if (index[i] < 0)
            return false;
        mapped.insert(index[i]);
    }
    return true;
}

/** The interaction groups, renumbered; false if one reaches outside the polymer. */
bool copyInteractionGroups(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index,
                           OpenMM::CustomNonbondedForce& copy) {
    for (int g = 0; g < force.getNumInteractionGroups(); g++) {
        std::set<int> set1, set2, mapped1, mapped2;
        force.getInteractionGroupParameters(g, set1, set2);
        if (!mapToPolymer(set1, index, mapped1) || !mapToPolymer(set2, index, mapped2))
            return false;
        copy.addInteractionGroup(mapped1, mapped2);
    }
    return true;
}

OpenMM::Force* copyCustomNonbonded(const OpenMM::CustomNonbondedForce& nonbonded, const std::vector<int>& index) {
    // Only interaction groups confine it to the polymer; a long-range correction depends on
    // the whole System.
    if (nonbonded.getNumInteractionGroups() == 0 || nonbonded.getUseLongRangeCorrection() ||
        nonbonded.getNumEnergyParameterDerivatives() > 0)
        return nullptr;
    std::unique_ptr<OpenMM::CustomNonbondedForce> copy(emptyNonbondedLike(nonbonded));
    copyNonbondedParticles(nonbonded, index, *copy);
    // One group of every polymer particle with every other is no restriction in the copy:
    // leave it out, so that OpenMM uses its neighbour list rather than all pairs.
    if (!isWholePolymerGroup(nonbonded, index, (size_t) copy->getNumParticles()) &&
        !copyInteractionGroups(nonbonded, index, *copy))
        return nullptr;
    return copy.release();
}

} // namespace

OpenMM::Force* DPDPlugin::copyOverPolymer(const OpenMM::Force& force, const std::vector<int>& index) {
    if (auto* bond = dynamic_cast<const OpenMM::HarmonicBondForce*>(&force))
        return copyHarmonicBonds(*bond, index);
    if (auto* bond = dynamic_cast<const OpenMM::CustomBondForce*>(&force))
        return copyCustomBonds(*bond, index);
    if (auto* nonbonded = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force))
        return copyCustomNonbonded(*nonbonded, index);
    return nullptr;
}

void DPDPlugin::syncBoxAndParameters(OpenMM::Context& target, const Vec3* box, const std::map<std::string, double>& parameters,
                                     Vec3* cachedBox) {
    if (box[0] != cachedBox[0] || box[1] != cachedBox[1] || box[2] != cachedBox[2]) {
        target.setPeriodicBoxVectors(box[0], box[1], box[2]);
        std::copy(box, box + 3, cachedBox);
    }
    const std::map<std::string, double>& targetParameters = target.getParameters();
    for (const auto& parameter : parameters) {
        auto it = targetParameters.find(parameter.first);
        if (it != targetParameters.end() && it->second != parameter.second)
            target.setParameter(parameter.first, parameter.second);
    }
}

namespace {

// Beyond these a polymer's fast forces are evaluated on the main Context's platform: the
// Reference platform evaluates ~20 terms per microsecond on one thread, and the pair list is
// rebuilt by going over every candidate pair.
const size_t SMALL_POLYMER = 2000;

std::string numberText(double x) {
    std::ostringstream text;
    text.precision(17);
    text << x;
    return text.str();
}

/**
 * The energy of a CustomNonbondedForce between two particles as a CustomBondForce's: zero
 * from the cutoff on (pairs closer than the cutoff interact, as in OpenMM's kernels), times
 * OpenMM's switching function if the force has one; the per-particle parameter p of the two
 * particles is then the bond's p1 and p2, as in the force's own expression.
 */
std::string pairEnergy(const OpenMM::CustomNonbondedForce& force) {
    if (force.getNonbondedMethod() == OpenMM::CustomNonbondedForce::NoCutoff)
        return force.getEnergyFunction();
    const std::string rc = numberText(force.getCutoffDistance());
    std::string energy = "select(step(r-" + rc + "), 0, dpdPairEnergy", definitions;
    if (force.getUseSwitchingFunction()) {
        const std::string rs = numberText(force.getSwitchingDistance());
        energy += "*select(step(r-" + rs + "), 1+dpdSwitchT^3*(-10+dpdSwitchT*(15-6*dpdSwitchT)), 1)";
        definitions = "; dpdSwitchT=(r-" + rs + ")/(" + rc + "-" + rs + ")";
    }
    return energy + ")" + definitions + "; dpdPairEnergy=" + force.getEnergyFunction();
}

/**
 * The pairs OpenMM's kernels evaluate for a CustomNonbondedForce with interaction groups, in
 * polymer indices: (i of set 1, j of set 2) once per group, none excluded or of a particle
 * with itself.  False if a group reaches outside the polymer, a pair is in two groups (how
 * often it then counts is left to OpenMM), or there are more than `limit`.
 */
bool groupPairs(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index, size_t limit,
                std::vector<std::pair<int, int>>& pairs) {
    std::set<std::pair<int, int>> excluded, seen;
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int i, j;
        force.getExclusionParticles(k, i, j);
        excluded.insert(std::make_pair(std::min(i, j), std::max(i, j)));
    }
    for (int g = 0; g < force.getNumInteractionGroups(); g++) {
        std::set<int> set1, set2;
        force.getInteractionGroupParameters(g, set1, set2);
        if (set1.size() * set2.size() > 2 * limit)
            return false;
        for (int i : set1)
            for (int j : set2) {
                const std::pair<int, int> pair(std::min(i, j), std::max(i, j));
                if (i == j || excluded.count(pair) != 0 || (i > j && set1.count(j) != 0 && set2.count(i) != 0))
                    continue;
                if (index[i] < 0 || index[j] < 0 || !seen.insert(pair).second || pairs.size() == limit)
                    return false;
                pairs.emplace_back(index[i], index[j]);
            }
    }
    return true;
}

/** r_j - r_i, periodic as OpenMM's kernels take it (ReferenceForce::getDeltaRPeriodic). */
Vec3 pairDelta(const Vec3& ri, const Vec3& rj, const Vec3* box, bool periodic) {
    Vec3 d = rj - ri;
    if (periodic) {
        d -= box[2] * std::floor(d[2] / box[2][2] + 0.5);
        d -= box[1] * std::floor(d[1] / box[1][1] + 0.5);
        d -= box[0] * std::floor(d[0] / box[0][0] + 0.5);
    }
    return d;
}

} // namespace

std::unique_ptr<PolymerForceContext> PolymerForceContext::create(const OpenMM::System& system, int fastGroups,
                                                                 const PolymerSelection& polymer, OpenMM::Platform& platform,
                                                                 const std::map<std::string, std::string>& properties) {
    std::unique_ptr<PolymerForceContext> fast(new PolymerForceContext(system, fastGroups, polymer));
    if (fast->makePairTables()) {
        fast->platform = &OpenMM::Platform::getPlatformByName("Reference");
    }
    else {
        fast->tables.clear();
        fast->platform = &platform;
        fast->properties = properties;
    }
    if (!fast->makeContext())
        return nullptr;
    return fast;
}

bool PolymerForceContext::makePairTables() {
    if (particles.size() > SMALL_POLYMER)
        return false;
    size_t candidates = 0;
    for (int f = 0; f < system.getNumForces(); f++) {
        const OpenMM::Force& force = system.getForce(f);
        auto* nonbonded = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force);
        if ((fastGroups & (1 << force.getForceGroup())) == 0 || nonbonded == nullptr)
            continue;
        if (!addPairTable(*nonbonded, PAIR_CANDIDATE_LIMIT - candidates))
            return false;
        candidates += tables.back().candidates.size();
    }
    return true;
}

bool PolymerForceContext::addPairTable(const OpenMM::CustomNonbondedForce& force, size_t limit) {
    // What a CustomBondForce cannot say (tabulated functions, computed values), or what
    // depends on more than the pair, stays with the copy of the force.
    bool computedValues = false;
#if OPENMMDPD_OPENMM_MAJOR >= 8
    computedValues = force.getNumComputedValues() > 0;
#endif
    if (force.getNumInteractionGroups() == 0 || force.getUseLongRangeCorrection() || force.getNumEnergyParameterDerivatives() > 0 ||
        force.getNumTabulatedFunctions() > 0 || computedValues)
        return false;
    PairTable table;
    table.force = &force;
    if (!groupPairs(force, index, limit, table.candidates))
        return false;
    const bool cutoff = force.getNonbondedMethod() != OpenMM::CustomNonbondedForce::NoCutoff;
    table.periodic = force.getNonbondedMethod() == OpenMM::CustomNonbondedForce::CutoffPeriodic;
    table.cutoff = force.getCutoffDistance();
    table.skin = cutoff ? LIST_SKIN * table.cutoff : 0;
    std::vector<double> values;
    for (int p : particles) {
        force.getParticleParameters(p, values);
        table.parameters.push_back(values);
    }
    table.capacity = 16;
    tables.push_back(std::move(table));
    return true;
}

/** The parameters of slot bond s: p1... of the first particle of its pair, p2... of the second. */
std::vector<double> PolymerForceContext::slotParameters(const PairTable& table, int s) {
    const std::pair<int, int> pair = (s < (int) table.listed.size() ? table.candidates[table.listed[s]] : std::make_pair(0, 0));
    std::vector<double> values = table.parameters[pair.first];
    values.insert(values.end(), table.parameters[pair.second].begin(), table.parameters[pair.second].end());
    return values;
}

OpenMM::CustomBondForce* PolymerForceContext::slotBonds(const PairTable& table) {
    const OpenMM::CustomNonbondedForce& force = *table.force;
    std::unique_ptr<OpenMM::CustomBondForce> bonds(new OpenMM::CustomBondForce(pairEnergy(force)));
    for (const char* which : {"1", "2"})
        for (int p = 0; p < force.getNumPerParticleParameters(); p++)
            bonds->addPerBondParameter(force.getPerParticleParameterName(p) + which);
    for (int p = 0; p < force.getNumGlobalParameters(); p++)
        bonds->addGlobalParameter(force.getGlobalParameterName(p), force.getGlobalParameterDefaultValue(p));
    bonds->setUsesPeriodicBoundaryConditions(table.periodic);
    for (int s = 0; s < table.capacity; s++)
        bonds->addBond(table.firstSlot + 2 * s, table.firstSlot + 2 * s + 1, slotParameters(table, s));
    return bonds.release();
}

bool PolymerForceContext::makeContext() {
    std::unique_ptr<OpenMM::System> side(new OpenMM::System());
    for (int p : particles)
        side->addParticle(system.getParticleMass(p));
    Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    side->setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    size_t table = 0;
    for (int f = 0; f < system.getNumForces(); f++) {
        const OpenMM::Force& force = system.getForce(f);
        if ((fastGroups & (1 << force.getForceGroup())) == 0)
            continue;
        if (table < tables.size() && tables[table].force == &force) {
            PairTable& pairs = tables[table++];
            pairs.firstSlot = side->getNumParticles();
            for (int s = 0; s < 2 * pairs.capacity; s++)
                side->addParticle(1.0);
            pairs.bonds = slotBonds(pairs);
            side->addForce(pairs.bonds);
            continue;
        }
        OpenMM::Force* copy = copyOverPolymer(force, index);
        if (copy == nullptr)
            return false;
        side->addForce(copy);
    }
    if (side->getNumForces() == 0)
        return false;
    sideContext.reset();
    sideSystem = std::move(side);
    sideIntegrator.reset(new OpenMM::VerletIntegrator(1.0));
    sideContext.reset(new OpenMM::Context(*sideSystem, *sideIntegrator, *platform, properties));
    sideContext->getState(0).getPeriodicBoxVectors(sideBox[0], sideBox[1], sideBox[2]);
    parkSlots();
    return true;
}

/** Every slot particle where no force acts: a pair at the cutoff distance (forces discarded anyway). */
void PolymerForceContext::parkSlots() {
    sidePositions.assign(sideSystem->getNumParticles(), Vec3());
    for (const PairTable& table : tables)
        for (int s = 0; s < table.capacity; s++)
            sidePositions[table.firstSlot + 2 * s + 1] = Vec3(table.cutoff, 0, 0);
}

bool PolymerForceContext::needsNewList(const Vec3* box) const {
    if (listPositions.empty())
        return true;
    double moved = 0, boxMoved = 0, skin = INFINITY;
    // A periodic pair's distance does not change when a particle is wrapped into the box:
    // only its move to the nearest image of where it was counts.
    const bool periodic = std::all_of(tables.begin(), tables.end(), [](const PairTable& table) { return table.periodic; });
    Vec3 low = polymerPositions[0], high = low;
    for (size_t k = 0; k < polymerPositions.size(); k++) {
        const Vec3 d = pairDelta(listPositions[k], polymerPositions[k], box, periodic);
        moved = std::max(moved, d.dot(d));
        for (int a = 0; a < 3; a++) {
            low[a] = std::min(low[a], polymerPositions[k][a]);
            high[a] = std::max(high[a], polymerPositions[k][a]);
        }
    }
    for (int a = 0; a < 3; a++)
        boxMoved += std::sqrt((box[a] - listBox[a]).dot(box[a] - listBox[a]));
    if (boxMoved > 0) {
        // A pair's image moves with each box vector times the number of boxes between the
        // two particles along it (at most about the polymer's extent over the box width),
        // and each particle's wrap into the box by at most the box's move.
        const double extent = std::max({high[0] - low[0], high[1] - low[1], high[2] - low[2]});
        const double width = std::min({box[0][0], box[1][1], box[2][2]});
        boxMoved *= 4 + 2 * std::ceil(extent / width);
    }
    for (const PairTable& table : tables)
        if (table.skin > 0)
            skin = std::min(skin, table.skin);
    // A pair comes closer by at most the moves of its two particles and of its image.
    return 2 * std::sqrt(moved) + boxMoved >= skin;
}

bool PolymerForceContext::listPairs(const Vec3* box) {
    listPositions = polymerPositions;
    std::copy(box, box + 3, listBox);
    const double width = std::min({box[0][0], box[1][1], box[2][2]});
    bool fits = true;
    for (PairTable& table : tables) {
        table.listed.clear();
        const double reach = table.cutoff + table.skin;
        // Within half the box OpenMM's periodic distance is the nearest image's, which the skin argument needs.
        const bool all = (table.skin == 0 || (table.periodic && 2 * reach > width));
        for (size_t c = 0; c < table.candidates.size(); c++) {
            const Vec3 d = pairDelta(polymerPositions[table.candidates[c].first], polymerPositions[table.candidates[c].second], box,
                                     table.periodic);
            if (all || d.dot(d) < reach * reach)
                table.listed.push_back((int) c);
        }
        fits = fits && (int) table.listed.size() <= table.capacity;
    }
    return fits;
}

void PolymerForceContext::listPairsAgain(const Vec3* box) {
    if (listPairs(box)) {
        for (PairTable& table : tables)
            if (table.force->getNumPerParticleParameters() > 0) {
                for (int s = 0; s < table.capacity; s++)
                    table.bonds->setBondParameters(s, table.firstSlot + 2 * s, table.firstSlot + 2 * s + 1, slotParameters(table, s));
                table.bonds->updateParametersInContext(*sideContext);
            }
        return;
    }
    // A table outgrew its slots: a new side Context with room for twice its pairs.
    for (PairTable& table : tables)
        table.capacity = std::max(table.capacity, 2 * (int) table.listed.size());
    makeContext();
}

void PolymerForceContext::compute(const std::vector<Vec3>& r, const Vec3* box, const std::map<std::string, double>& parameters,
                                  std::vector<Vec3>& fast) {
    polymerPositions.resize(particles.size());
    for (size_t k = 0; k < particles.size(); k++)
        polymerPositions[k] = r[particles[k]];
    if (!tables.empty() && needsNewList(box))
        listPairsAgain(box);
    std::copy(polymerPositions.begin(), polymerPositions.end(), sidePositions.begin());
    for (const PairTable& table : tables)
        for (size_t s = 0; s < table.listed.size(); s++) {
            const std::pair<int, int>& pair = table.candidates[table.listed[s]];
            sidePositions[table.firstSlot + 2 * s] = polymerPositions[pair.first];
            sidePositions[table.firstSlot + 2 * s + 1] = polymerPositions[pair.second];
        }
    syncBoxAndParameters(*sideContext, box, parameters, sideBox);
    sideContext->setPositions(sidePositions);
    const OpenMM::State state = sideContext->getState(OpenMM::State::Forces);
    const std::vector<Vec3>& f = state.getForces();
    fast.assign(f.begin(), f.begin() + particles.size());
    for (const PairTable& table : tables)
        for (size_t s = 0; s < table.listed.size(); s++) {
            const std::pair<int, int>& pair = table.candidates[table.listed[s]];
            fast[pair.first] += f[table.firstSlot + 2 * s];
            fast[pair.second] += f[table.firstSlot + 2 * s + 1];
        }
}
