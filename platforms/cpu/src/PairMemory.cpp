#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/PairMemory.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <istream>
#include <ostream>

using namespace DPDPlugin;

PairMemory::PairMemory(const DPDPairParameters& parameters, const PairRandom& random, ParallelExecutor& executor) :
        parameters(parameters), random(random), executor(executor), inRangeStep(-1),
        inRangeStart(parameters.getNumParticles() + 1, 0), archived(parameters.getNumParticles()) {
}

const PairMemory::Archived* PairMemory::findArchived(int i, int j) const {
    const std::vector<Archived>& list = archived[i];
    auto it = std::lower_bound(list.begin(), list.end(), j, [](const Archived& a, int key) { return a.j < key; });
    return (it != list.end() && it->j == j) ? &*it : nullptr;
}

void PairMemory::archive(int i, int j, double s, long long step) {
    std::vector<Archived>& list = archived[i];
    auto it = std::lower_bound(list.begin(), list.end(), j, [](const Archived& a, int key) { return a.j < key; });
    if (it != list.end() && it->j == j)
        *it = Archived{j, s, step};
    else
        list.insert(it, Archived{j, s, step});
}

double PairMemory::recall(int i, int j, bool known, double s, long long last, long long step,
                          const AuxiliaryRecurrence& recurrence) const {
    const long long gap = step - last;
    if (known && gap == 0)
        return s;
    const double variance = recurrence.alpha * parameters.pairThermostatGamma(i, j) * recurrence.variancePerLambda;
    return recurrence.recall(known, s, gap, variance, random.gaussian(PairRandom::AuxiliaryRecall, step, i, j));
}

template <class PairUpdate>
void PairMemory::merge(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence,
                       std::vector<double>& pairS, PairUpdate update) {
    const int n = parameters.getNumParticles();
    // Group the new pairs by their lower particle (counting sort, in pair-list order).
    groupStart.assign(n + 1, 0);
    for (const PairGeometry& p : pairs)
        groupStart[std::min(p.i, p.j) + 1]++;
    for (int i = 0; i < n; i++)
        groupStart[i + 1] += groupStart[i];
    fill.assign(groupStart.begin(), groupStart.end() - 1);
    groupPairs.resize(pairs.size());
    for (size_t k = 0; k < pairs.size(); k++)
        groupPairs[fill[std::min(pairs[k].i, pairs[k].j)]++] = (int) k;
    nextInRange.resize(pairs.size());
    pairS.resize(pairs.size());
    executor.execute([&](int w) {
        size_t begin, end;
        executor.range(w, n, begin, end);
        for (size_t i = begin; i < end; i++) {
            auto upper = [&](int k) { return std::max(pairs[k].i, pairs[k].j); };
            std::sort(groupPairs.begin() + groupStart[i], groupPairs.begin() + groupStart[i + 1],
                      [&](int a, int b) { return upper(a) < upper(b); });
            const InRange* old = inRange.data() + inRangeStart[i];
            const InRange* oldEnd = inRange.data() + inRangeStart[i + 1];
            for (int g = groupStart[i]; g < groupStart[i + 1]; g++) {
                const int k = groupPairs[g];
                const int j = upper(k);
                for (; old != oldEnd && old->j < j; ++old)
                    update.leaving((int) i, *old);
                const bool wasInRange = (old != oldEnd && old->j == j);
                const double wR2 = pairs[k].wR * pairs[k].wR;
                const double s = update.inRange((int) i, j, wasInRange ? old : nullptr, wR2);
                if (wasInRange)
                    ++old;
                nextInRange[g] = InRange{j, s, wR2};
                pairS[k] = s;
            }
            for (; old != oldEnd; ++old)
                update.leaving((int) i, *old);
            update.collectGarbage((int) i);
        }
    });
    inRange.swap(nextInRange);
    inRangeStart.swap(groupStart);
}

void PairMemory::bind(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence,
                      std::vector<double>& pairS) {
    struct Bind {
        PairMemory& memory;
        long long step, previous;
        const AuxiliaryRecurrence& recurrence;
        double inRange(int i, int j, const InRange* old, double wR2) const {
            if (old != nullptr)
                return memory.recall(i, j, true, old->s, previous, step, recurrence);
            const Archived* a = memory.findArchived(i, j);
            return memory.recall(i, j, a != nullptr, a ? a->s : 0, a ? a->step : 0, step, recurrence);
        }
        void leaving(int i, const InRange& old) const {
            memory.archive(i, old.j, old.s, previous);
        }
        void collectGarbage(int i) const {}
    };
    merge(pairs, step, recurrence, pairS, Bind{*this, step, inRangeStep, recurrence});
    inRangeStep = step;
}

void PairMemory::advance(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence,
                         std::vector<double>& pairS) {
    if (inRangeStep != step)
        throw OpenMM::OpenMMException("EDPDIntegrator: internal error: the pair variables are not at the current step");
    struct Advance {
        PairMemory& memory;
        long long step;
        const AuxiliaryRecurrence& recurrence;
        bool collect;
        // One step of the recurrence; h = -rc wR^2 / 2 up to a constant.
        double next(int i, int j, double s, double wR2Old, double wR2New) const {
            const double lambda = recurrence.alpha * memory.parameters.pairThermostatGamma(i, j);
            const double dh = AuxiliaryRecurrence::dh(memory.parameters.pairCutoff(i, j), wR2Old, wR2New);
            return recurrence.next(s, lambda, dh, memory.random.gaussian(PairRandom::AuxiliaryNoise, step + 1, i, j));
        }
        double inRange(int i, int j, const InRange* old, double wR2) const {
            if (old != nullptr)
                return next(i, j, old->s, old->wR2, wR2);
            const Archived* a = memory.findArchived(i, j);
            const double s = memory.recall(i, j, a != nullptr, a ? a->s : 0, a ? a->step : 0, step, recurrence);
            return next(i, j, s, 0, wR2);
        }
        void leaving(int i, const InRange& old) const {
            memory.archive(i, old.j, next(i, old.j, old.s, old.wR2, 0), step + 1);
        }
        void collectGarbage(int i) const {
            if (!collect)
                return;
            std::vector<Archived>& list = memory.archived[i];
            const long long now = step + 1, forget = recurrence.forgetSteps;
            list.erase(std::remove_if(list.begin(), list.end(), [&](const Archived& a) { return now - a.step >= forget; }),
                       list.end());
        }
    };
    const long long interval = std::max(1LL, recurrence.forgetSteps / 4);
    merge(pairs, step, recurrence, pairS, Advance{*this, step, recurrence, (step + 1) % interval == 0});
    inRangeStep = step + 1;
}

bool PairMemory::find(int i, int j, double& s, long long& step) const {
    if (i > j)
        std::swap(i, j);
    if (i < 0 || j >= parameters.getNumParticles())
        return false;
    for (int k = inRangeStart[i]; k < inRangeStart[i + 1]; k++)
        if (inRange[k].j == j) {
            s = inRange[k].s;
            step = inRangeStep;
            return true;
        }
    const Archived* a = findArchived(i, j);
    if (a == nullptr)
        return false;
    s = a->s;
    step = a->step;
    return true;
}

long long PairMemory::size() const {
    long long total = (long long) inRange.size();
    for (const std::vector<Archived>& list : archived)
        total += (long long) list.size();
    return total;
}


void PairMemory::write(std::ostream& stream) const {
    putField<int64_t>(stream, inRangeStep);
    putField<uint64_t>(stream, archived.size());
    putField<uint64_t>(stream, inRange.size());
    for (int start : inRangeStart)
        putField<int32_t>(stream, start);
    for (const InRange& p : inRange) {
        putField<int32_t>(stream, p.j);
        putField<double>(stream, p.s);
        putField<double>(stream, p.wR2);
    }
    for (const std::vector<Archived>& list : archived) {
        putField<uint64_t>(stream, list.size());
        for (const Archived& a : list) {
            putField<int32_t>(stream, a.j);
            putField<double>(stream, a.s);
            putField<int64_t>(stream, a.step);
        }
    }
}

PairMemory::Saved PairMemory::read(CheckpointReader& reader) const {
    Saved saved;
    saved.inRangeStep = reader.take<int64_t>("the step of the pair variables");
    if (std::abs(saved.inRangeStep) > MAX_STEP_NUMBER)
        reader.damaged("the pair variables are of step " + std::to_string(saved.inRangeStep));
    if (reader.take<uint64_t>("the particle count of the pair variables") != archived.size())
        reader.damaged("the pair variables are for another particle count");
    readInRange(reader, saved);
    readArchived(reader, saved);
    return saved;
}

// Offsets monotone from 0 to the pair count, partners above their particle, sorted, and
// finite values: what merge() and find() rely on.
void PairMemory::readInRange(CheckpointReader& reader, Saved& saved) const {
    const int n = (int) archived.size();
    saved.inRange.resize(reader.takeCount("the number of pairs in range", 20));
    saved.inRangeStart.resize(n + 1);
    for (int& start : saved.inRangeStart)
        start = reader.take<int32_t>("the pairs' offsets");
    if (saved.inRangeStart[0] != 0 || saved.inRangeStart[n] != (long long) saved.inRange.size())
        reader.damaged("the pairs' offsets do not run from 0 to the number of pairs");
    if (saved.inRangeStep == -1 && !saved.inRange.empty())
        reader.damaged("pairs in range before the first step");
    for (InRange& p : saved.inRange) {
        p.j = reader.take<int32_t>("a pair's partner");
        p.s = reader.takeFinite("a pair variable");
        p.wR2 = reader.takeFinite("a pair weight");
        if (p.wR2 < 0 || p.wR2 > 1)
            reader.damaged("a pair weight wR^2 is " + numberText(p.wR2) + ", outside [0, 1]");
    }
    for (int i = 0; i < n; i++) {
        const int begin = saved.inRangeStart[i], end = saved.inRangeStart[i + 1];
        if (begin > end)
            reader.damaged("the pairs' offsets decrease at particle " + std::to_string(i));
        for (int k = begin; k < end; k++)
            if (saved.inRange[k].j <= (k > begin ? saved.inRange[k - 1].j : i) || saved.inRange[k].j >= n)
                reader.damaged("particle " + std::to_string(i) + " has the partner " + std::to_string(saved.inRange[k].j) +
                               " out of order or out of range");
    }
}

void PairMemory::readArchived(CheckpointReader& reader, Saved& saved) const {
    const int n = (int) archived.size();
    saved.archived.resize(n);
    for (int i = 0; i < n; i++) {
        std::vector<Archived>& list = saved.archived[i];
        list.resize(reader.takeCount("the number of archived pairs", 20));
        for (size_t k = 0; k < list.size(); k++) {
            Archived& a = list[k];
            a.j = reader.take<int32_t>("an archived pair's partner");
            a.s = reader.takeFinite("an archived pair variable");
            a.step = reader.take<int64_t>("the step of an archived pair");
            if (a.j <= (k > 0 ? list[k - 1].j : i) || a.j >= n)
                reader.damaged("particle " + std::to_string(i) + " has the archived partner " + std::to_string(a.j) +
                               " out of order or out of range");
            if (a.step > saved.inRangeStep || a.step < -MAX_STEP_NUMBER)
                reader.damaged("an archived pair variable is of step " + std::to_string(a.step) + ", after the pairs in range (" +
                               std::to_string(saved.inRangeStep) + ")");
        }
    }
}

void PairMemory::restore(Saved&& saved) {
    inRangeStep = saved.inRangeStep;
    inRangeStart.swap(saved.inRangeStart);
    inRange.swap(saved.inRange);
    archived.swap(saved.archived);
}

void PairMemory::renumberSteps(long long step) {
    if (inRangeStep < 0 || inRangeStep == step)
        return;
    const long long shift = step - inRangeStep;
    for (std::vector<Archived>& list : archived)
        for (Archived& a : list)
            a.step += shift;
    inRangeStep = step;
}

void PairMemory::clear() {
    inRangeStep = -1;
    std::fill(inRangeStart.begin(), inRangeStart.end(), 0);
    inRange.clear();
    for (std::vector<Archived>& list : archived)
        list.clear();
}
