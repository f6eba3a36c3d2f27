#include "openmmdpd/CommonEDPDDynamics.h"
#include "CommonDPDKernelSources.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>
#include <cstdlib>

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

// An entry's state (kernels/edpd.cc): in range, archived, or both.
constexpr int IN_RANGE = 1, ARCHIVED = 2;
constexpr int FIRST_CAPACITY = 32;
// Where the kernels' cell-list arguments start, and those after them.
constexpr int MERGE_CELL_ARGS = 11, MERGE_TABLE_ARGS = MERGE_CELL_ARGS + CommonCellList::NUM_ARGS;
constexpr int FORCE_CELL_ARGS = 8, FORCE_TABLE_ARGS = FORCE_CELL_ARGS + CommonCellList::NUM_ARGS;

} // namespace

CommonEDPDDynamics::CommonEDPDDynamics(ComputeContext& cc, const System& system, const EDPDIntegrator& integrator,
                                       const std::string& platform) :
        CommonDynamics(cc, system, integrator, platform, {CommonDPDKernelSources::dpdvv, CommonDPDKernelSources::edpd}, false) {
    ContextSelector selector(cc);
    const int n = std::max(numAtoms(), 1);
    pairCells.reset(new CommonCellList(cc, program, name, system.usesPeriodicBoundaryConditions(), true));
    auxiliaryForce.initialize<long long>(cc, 3 * n, "edpdAuxiliaryForce");
    needed.initialize<int>(cc, 1, "edpdNeeded");
    for (Table& table : tables)
        allocate(table, FIRST_CAPACITY);
    capacity = FIRST_CAPACITY;
    mergeKernel = createKernelWithArgs(program, "edpdMergePairs", MERGE_TABLE_ARGS + 29);
    forceKernel = createKernelWithArgs(program, "edpdPairForces", FORCE_TABLE_ARGS + 9);
    carryKernel = createKernelWithArgs(program, "edpdCarryForce", 11);
    renumberKernel = createKernelWithArgs(program, "edpdRenumberSteps", 5);
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    driftKernel = program->createKernel("dpdvvPart1");
    driftKernel->addArg(numAtoms());
    addArrayArgs(driftKernel, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &carriedForce, &velocity});
    driftKernel->addArg();  // dt and the move bound: set per step
    driftKernel->addArg();
    driftKernel->addArg(status);
    driftKernel->addArg(moveValue);
    addDriftArgs(driftKernel);
}

void CommonEDPDDynamics::allocate(Table& table, int entries) {
    const int size = std::max(numAtoms(), 1) * entries;
    const int mixedSize = mixedIsDouble(cc) ? sizeof(double) : sizeof(float);
    sizeArray(table.partner, size, sizeof(int), "edpdPartner");
    sizeArray(table.flags, size, sizeof(int), "edpdFlags");
    sizeArray(table.value, size, mixedSize, "edpdValue");
    sizeArray(table.weight2, size, mixedSize, "edpdWeight2");
    sizeArray(table.archived, size, mixedSize, "edpdArchived");
    sizeArray(table.archivedStep, size, sizeof(long long), "edpdArchivedStep");
    sizeArray(table.count, std::max(numAtoms(), 1), sizeof(int), "edpdCount");
    cc.clearBuffer(table.count);
    sizeArray(candidatePartner, size, sizeof(int), "edpdCandidatePartner");
    sizeArray(candidateWeight2, size, mixedSize, "edpdCandidateWeight2");
}

void CommonEDPDDynamics::sizeArray(ComputeArray& array, int size, int elementSize, const std::string& arrayName) {
    if (!array.isInitialized())
        array.initialize(cc, size, elementSize, arrayName);
    else if ((int) array.getSize() != size)
        array.resize(size);
}

CommonEDPDDynamics::Rows CommonEDPDDynamics::download(const Table& constTable) const {
    Table& table = const_cast<Table&>(constTable);
    std::vector<int> partner, flags, count;
    std::vector<long long> archivedStep;
    table.partner.download(partner);
    table.flags.download(flags);
    table.count.download(count);
    table.archivedStep.download(archivedStep);
    const std::vector<double> value = downloadMixed(cc, table.value), weight2 = downloadMixed(cc, table.weight2),
                              archived = downloadMixed(cc, table.archived);
    Rows rows(numAtoms());
    for (int a = 0; a < numAtoms(); a++)
        for (int e = a * capacity; e < a * capacity + count[a]; e++)
            rows[a].push_back(Entry{partner[e], flags[e], value[e], weight2[e], archived[e], archivedStep[e]});
    return rows;
}

void CommonEDPDDynamics::upload(Table& table, const Rows& rows) {
    const size_t size = std::max(numAtoms(), 1) * (size_t) capacity;
    std::vector<int> partner(size, 0), flags(size, 0), count(std::max(numAtoms(), 1), 0);
    std::vector<double> value(size, 0), weight2(size, 0), archived(size, 0);
    std::vector<long long> archivedStep(size, 0);
    for (int a = 0; a < (int) rows.size(); a++) {
        count[a] = (int) rows[a].size();
        for (int k = 0; k < count[a]; k++) {
            const Entry& e = rows[a][k];
            const size_t at = a * (size_t) capacity + k;
            partner[at] = e.partner;
            flags[at] = e.flags;
            value[at] = e.value;
            weight2[at] = e.weight2;
            archived[at] = e.archived;
            archivedStep[at] = e.archivedStep;
        }
    }
    table.partner.upload(partner);
    table.flags.upload(flags);
    table.count.upload(count);
    table.archivedStep.upload(archivedStep);
    uploadMixed(cc, table.value, value, "edpdValue");
    uploadMixed(cc, table.weight2, weight2, "edpdWeight2");
    uploadMixed(cc, table.archived, archived, "edpdArchived");
}

void CommonEDPDDynamics::grow(int entries) {
    const Rows rows = download(tables[current]);
    capacity = std::max(entries + entries / 4 + 8, capacity);
    for (Table& table : tables)
        allocate(table, capacity);
    upload(tables[current], rows);
}

void CommonEDPDDynamics::merge(long long step, bool advance, const AuxiliaryRecurrence& recurrence) {
    pairCells->build(parameters.getMaxCutoff());
    const long long now = step + 1, interval = std::max(1LL, recurrence.forgetSteps / 4);
    while (true) {
        const Table& from = tables[current];
        Table& to = tables[1 - current];
        mergeKernel->setArg(0, numAtoms());
        ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
        setArrayArgs(mergeKernel, 1, {&cc.getPosq(), &posqCorrection, &cc.getAtomIndexArray(), &velocity, &atomType});
        mergeKernel->setArg(6, parameters.getTable().getNumTypes());
        setArrayArgs(mergeKernel, 7, {&typeParams, &exceptionStart, &exceptionPartner, &exceptionFactor});
        pairCells->setArgs(mergeKernel, MERGE_CELL_ARGS);
        int arg = MERGE_TABLE_ARGS;
        mergeKernel->setArg(arg++, capacity);
        for (const Table* t : {&from, (const Table*) &to})
            for (const ComputeArray* a : {&t->partner, &t->flags, &t->value, &t->weight2, &t->archived, &t->archivedStep, &t->count})
                mergeKernel->setArg(arg++, const_cast<ComputeArray&>(*a));
        setArrayArgs(mergeKernel, arg, {&candidatePartner, &candidateWeight2});
        arg += 2;
        mergeKernel->setArg(arg++, (unsigned int) random.getSeed());
        mergeKernel->setArg(arg++, step);
        mergeKernel->setArg(arg++, inRangeStep);
        mergeKernel->setArg(arg++, advance ? 1 : 0);
        mergeKernel->setArg(arg++, recurrence.forgetSteps);
        mergeKernel->setArg(arg++, advance && now % interval == 0 ? 1 : 0);
        for (double value : {recurrence.rho, recurrence.invD, recurrence.noisePerLambda, recurrence.variancePerLambda, recurrence.alpha})
            setMixedArg(cc, mergeKernel, arg++, value);
        mergeKernel->setArg(arg++, needed);
        cc.clearBuffer(needed);
        mergeKernel->execute(numAtoms());
        std::vector<int> largest;
        needed.download(largest);
        if (largest[0] <= capacity)
            break;
        grow(largest[0]);
    }
    current = 1 - current;
    inRangeStep = advance ? step + 1 : step;
    cacheValid = false;
}

void CommonEDPDDynamics::carryForce(bool kick, double dt, bool virial) {
    const Table& table = tables[current];
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    forceKernel->setArg(0, numAtoms());
    setArrayArgs(forceKernel, 1, {&cc.getPosq(), &posqCorrection, &cc.getAtomIndexArray(), &velocity, &atomType});
    forceKernel->setArg(6, parameters.getTable().getNumTypes());
    forceKernel->setArg(7, typeParams);
    pairCells->setArgs(forceKernel, FORCE_CELL_ARGS);
    forceKernel->setArg(FORCE_TABLE_ARGS, capacity);
    int arg = FORCE_TABLE_ARGS + 1;
    for (const ComputeArray* a : {&table.partner, &table.flags, &table.value, &table.count})
        forceKernel->setArg(arg++, const_cast<ComputeArray&>(*a));
    forceKernel->setArg(arg++, auxiliaryForce);
    forceKernel->setArg(arg++, virial ? 1 : 0);
    forceKernel->setArg(arg++, cc.getPaddedNumAtoms());
    if (virial)
        clearVirialRows(cc.getPaddedNumAtoms());
    forceKernel->setArg(arg++, virialRows);
    forceKernel->execute(numAtoms());
    if (virial)
        addVirialRows(cc.getPaddedNumAtoms(), 1);
    carryKernel->setArg(0, numAtoms());
    carryKernel->setArg(1, cc.getPaddedNumAtoms());
    setArrayArgs(carryKernel, 2, {&cc.getVelm(), &cc.getAtomIndexArray(), &cc.getLongForceBuffer(), &auxiliaryForce, &carriedForce});
    carryKernel->setArg(7, kick ? 1 : 0);
    setMixedArg(cc, carryKernel, 8, dt);
    setMixedArg(cc, carryKernel, 9, velocityBound());
    carryKernel->setArg(10, status);
    carryKernel->execute(numAtoms());
}

void CommonEDPDDynamics::renumberSteps(long long step) {
    if (inRangeStep < 0 || inRangeStep == step)
        return;
    Table& table = tables[current];
    renumberKernel->setArg(0, numAtoms());
    renumberKernel->setArg(1, capacity);
    setArrayArgs(renumberKernel, 2, {&table.count, &table.archivedStep});
    renumberKernel->setArg(4, step - inRangeStep);
    renumberKernel->execute(numAtoms());
    inRangeStep = step;
    cacheValid = false;
}

void CommonEDPDDynamics::step(ContextImpl& context, const EDPDIntegrator& integrator) {
    ContextSelector selector(cc);
    const double dt = integrator.getStepSize();
    const int groups = integrator.getIntegrationForceGroups();
    const long long now = cc.getStepCount();
    const AuxiliaryRecurrence recurrence(integrator.getAlpha(), dt, parameters.getKT(), integrator.getScheme() == EDPDIntegrator::Symmetric);
    renumberSteps(now);
    if (!carriedIsValid(context)) {
        // A start, or a state set from outside: the pairs in range now, with the s they carry.
        gatherVelocities();
        conservativeForce(context, groups);
        merge(now, false, recurrence);
        carryForce(false, dt, false);
        carried.setValid();
    }
    // p += dt/2 F;  r += dt p/m
    setMixedArg(cc, driftKernel, 7, dt);
    setMixedArg(cc, driftKernel, 8, maxMove2());
    driftKernel->execute(numAtoms());
    constrainDrift(dt, integrator.getConstraintTolerance());
    finishDrift(dt, true);
    // s^{n+1} from s^n and h(r^{n+1}) - h(r^n);  p += dt/2 F(r^{n+1}, s^{n+1})
    conservativeForce(context, groups);
    merge(now, true, recurrence);
    carryForce(true, dt, thermostatVirial != nullptr);
    constrainVelocities(integrator.getConstraintTolerance());
    checkStatus(context, now + 1);
    finishStep(dt);
}

const CommonEDPDDynamics::Rows& CommonEDPDDynamics::hostRows() const {
    if (!cacheValid) {
        ContextSelector selector(cc);
        cache = download(tables[current]);
        cacheValid = true;
    }
    return cache;
}

bool CommonEDPDDynamics::getPairVariable(int i, int j, double& value, long long& step) const {
    if (i == j || i < 0 || j < 0 || i >= numAtoms() || j >= numAtoms())
        return false;
    for (const Entry& e : hostRows()[std::min(i, j)]) {
        if (e.partner != std::max(i, j))
            continue;
        value = (e.flags & IN_RANGE) ? e.value : e.archived;
        step = (e.flags & IN_RANGE) ? inRangeStep : e.archivedStep;
        return true;
    }
    return false;
}

long long CommonEDPDDynamics::getNumPairVariables() const {
    long long total = 0;
    for (const std::vector<Entry>& row : hostRows())
        for (const Entry& e : row)
            total += ((e.flags & IN_RANGE) ? 1 : 0) + ((e.flags & ARCHIVED) ? 1 : 0);
    return total;
}

void CommonEDPDDynamics::saveExtraState(std::ostream& stream) const {
    putField<int32_t>(stream, numAtoms());
    putField<int64_t>(stream, inRangeStep);
    for (const std::vector<Entry>& row : hostRows()) {
        putField<uint64_t>(stream, row.size());
        for (const Entry& e : row) {
            putField<int32_t>(stream, e.partner);
            putField<int32_t>(stream, e.flags);
            putField<double>(stream, e.value);
            putField<double>(stream, e.weight2);
            putField<double>(stream, e.archived);
            putField<int64_t>(stream, e.archivedStep);
        }
    }
}

void CommonEDPDDynamics::loadExtraState(CheckpointReader& reader) {
    const int n = numAtoms();
    if (reader.take<int32_t>("the particle count of the pair variables") != n)
        reader.damaged("the pair variables are for another particle count");
    loadedStep = reader.take<int64_t>("the step of the pair variables");
    if (std::abs(loadedStep) > MAX_STEP_NUMBER)
        reader.damaged("the pair variables are of step " + std::to_string(loadedStep));
    loaded.assign(n, {});
    for (int a = 0; a < n; a++) {
        for (uint64_t count = reader.takeCount("the number of pair variables of a particle", 40); count > 0; count--) {
            Entry e;
            e.partner = reader.take<int32_t>("a pair");
            e.flags = reader.take<int32_t>("a pair variable's state");
            e.value = reader.takeFinite("a pair variable");
            e.weight2 = reader.takeFinite("a pair weight");
            e.archived = reader.takeFinite("an archived pair variable");
            e.archivedStep = reader.take<int64_t>("the step of an archived pair");
            const int previous = loaded[a].empty() ? a : loaded[a].back().partner;
            if (e.partner <= previous || e.partner >= n)
                reader.damaged("a pair variable of particle " + std::to_string(a) + " is for particle " + std::to_string(e.partner) +
                               ", not one above " + std::to_string(previous) + " and below " + std::to_string(n));
            if (e.flags < 1 || e.flags > (IN_RANGE | ARCHIVED) || ((e.flags & IN_RANGE) && loadedStep < 0))
                reader.damaged("a pair variable's state is " + std::to_string(e.flags));
            if (e.weight2 < 0 || e.weight2 > 1)
                reader.damaged("a pair weight w^2 is " + numberText(e.weight2) + ", outside [0, 1]");
            if ((e.flags & ARCHIVED) && (e.archivedStep > loadedStep || e.archivedStep < -MAX_STEP_NUMBER))
                reader.damaged("an archived pair variable is of step " + std::to_string(e.archivedStep) + ", after the pairs in range (" +
                               std::to_string(loadedStep) + ")");
            loaded[a].push_back(e);
        }
    }
}

void CommonEDPDDynamics::commitExtraState() {
    ContextSelector selector(cc);
    size_t longest = 0;
    for (const std::vector<Entry>& row : loaded)
        longest = std::max(longest, row.size());
    if ((int) longest > capacity) {
        capacity = (int) longest + (int) longest / 4 + 8;
        for (Table& table : tables)
            allocate(table, capacity);
    }
    upload(tables[current], loaded);
    inRangeStep = loadedStep;
    loaded.clear();
    cacheValid = false;
}

void CommonEDPDDynamics::resetExtraState() {
    ContextSelector selector(cc);
    for (Table& table : tables)
        cc.clearBuffer(table.count);
    inRangeStep = -1;
    cacheValid = false;
}
