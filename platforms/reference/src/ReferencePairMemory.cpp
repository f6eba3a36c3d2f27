#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/ReferencePairMemory.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cstdlib>
#include <cstdint>
#include <istream>
#include <ostream>

using namespace DPDPlugin;

double ReferencePairMemory::lambda(const Key& k, const AuxiliaryRecurrence& recurrence) const {
    return recurrence.alpha * parameters.pairThermostatGamma(k.first, k.second);
}

double ReferencePairMemory::catchUp(const Key& k, bool known, double s, long long last, long long step,
                                    const AuxiliaryRecurrence& recurrence) const {
    if (known && step == last)
        return s;  // nothing to catch up
    // With h constant, `step - last` steps of the recurrence in closed form; a fresh draw
    // from N(0, lambda V) if never seen or forgotten.
    const double variance = lambda(k, recurrence) * recurrence.variancePerLambda;
    const double xi = random.gaussian(PairRandom::AuxiliaryRecall, step, k.first, k.second);
    return recurrence.recall(known, s, step - last, variance, xi);
}

double ReferencePairMemory::recallArchived(const Key& k, long long step, const AuxiliaryRecurrence& recurrence) const {
    const auto a = archived.find(k);
    if (a == archived.end())
        return catchUp(k, false, 0, 0, step, recurrence);
    return catchUp(k, true, a->second.s, a->second.step, step, recurrence);
}

double ReferencePairMemory::nextValue(const Key& k, double s, double wR2Old, double wR2New, long long step,
                                      const AuxiliaryRecurrence& recurrence) const {
    // (1 + alpha dt) s^{n+1} = s^n + lambda [h(r^{n+1}) - h(r^n)] + sqrt(2 kT lambda alpha dt) w
    // (or its symmetric form), w keyed by the step it leads to.
    const double dh = AuxiliaryRecurrence::dh(parameters.pairCutoff(k.first, k.second), wR2Old, wR2New);
    const double w = random.gaussian(PairRandom::AuxiliaryNoise, step + 1, k.first, k.second);
    return recurrence.next(s, lambda(k, recurrence), dh, w);
}

void ReferencePairMemory::bind(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence) {
    std::map<Key, InRange> now;
    for (const PairGeometry& p : pairs) {
        const Key k = key(p.i, p.j);
        const auto old = inRange.find(k);
        double s;
        if (old != inRange.end())
            s = catchUp(k, true, old->second.s, inRangeStep, step, recurrence);
        else
            s = recallArchived(k, step, recurrence);
        now[k] = InRange{s, p.wR * p.wR};
    }
    // In range before, not now: archived as they are.
    for (const auto& old : inRange)
        if (now.count(old.first) == 0)
            archived[old.first] = Archived{old.second.s, inRangeStep};
    inRange.swap(now);
    inRangeStep = step;
}

void ReferencePairMemory::advance(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence) {
    if (inRangeStep != step)
        throw OpenMM::OpenMMException("EDPDIntegrator: internal error: the pair variables are not at the current step");
    std::map<Key, InRange> now;
    for (const PairGeometry& p : pairs) {
        const Key k = key(p.i, p.j);
        const double wR2 = p.wR * p.wR;
        const auto old = inRange.find(k);
        double s;
        if (old != inRange.end())
            s = nextValue(k, old->second.s, old->second.wR2, wR2, step, recurrence);
        else  // coming into range: out of range at r^n (wR = 0), brought up to step n first
            s = nextValue(k, recallArchived(k, step, recurrence), 0, wR2, step, recurrence);
        now[k] = InRange{s, wR2};
    }
    // Leaving range: one last step to h(r^{n+1}) = rc/2 (wR = 0), archived at step n + 1.
    for (const auto& old : inRange)
        if (now.count(old.first) == 0)
            archived[old.first] = Archived{nextValue(old.first, old.second.s, old.second.wR2, 0, step, recurrence), step + 1};
    inRange.swap(now);
    inRangeStep = step + 1;
    forget(step + 1, recurrence);
}

void ReferencePairMemory::forget(long long now, const AuxiliaryRecurrence& recurrence) {
    // Memory only: a pair away this long is drawn anew on return whether it is kept or not.
    // The schedule is the CPU platform's, so that getNumPairVariables() agrees with it.
    const long long interval = std::max(1LL, recurrence.forgetSteps / 4);
    if (now % interval != 0)
        return;
    for (auto a = archived.begin(); a != archived.end();) {
        if (now - a->second.step >= recurrence.forgetSteps)
            a = archived.erase(a);
        else
            ++a;
    }
}

double ReferencePairMemory::inRangeValue(int i, int j) const {
    const auto p = inRange.find(key(i, j));
    if (p == inRange.end())
        throw OpenMM::OpenMMException("EDPDIntegrator: internal error: a pair in range has no pair variable");
    return p->second.s;
}

bool ReferencePairMemory::find(int i, int j, double& s, long long& step) const {
    const Key k = key(i, j);
    const auto p = inRange.find(k);
    if (p != inRange.end()) {
        s = p->second.s;
        step = inRangeStep;
        return true;
    }
    const auto a = archived.find(k);
    if (a != archived.end()) {
        s = a->second.s;
        step = a->second.step;
        return true;
    }
    return false;
}


void ReferencePairMemory::write(std::ostream& stream) const {
    putField<int32_t>(stream, parameters.getNumParticles());
    putField<int64_t>(stream, inRangeStep);
    putField<uint64_t>(stream, inRange.size());
    for (const auto& p : inRange) {
        putField<int32_t>(stream, p.first.first);
        putField<int32_t>(stream, p.first.second);
        putField<double>(stream, p.second.s);
        putField<double>(stream, p.second.wR2);
    }
    putField<uint64_t>(stream, archived.size());
    for (const auto& a : archived) {
        putField<int32_t>(stream, a.first.first);
        putField<int32_t>(stream, a.first.second);
        putField<double>(stream, a.second.s);
        putField<int64_t>(stream, a.second.step);
    }
}

ReferencePairMemory::Saved ReferencePairMemory::read(CheckpointReader& reader) const {
    const int n = parameters.getNumParticles();
    if (reader.take<int32_t>("the particle count of the pair variables") != n)
        reader.damaged("the pair variables are for another particle count");
    auto takeKey = [&]() {
        const int i = reader.take<int32_t>("a pair"), j = reader.take<int32_t>("a pair");
        if (i < 0 || i >= j || j >= n)
            reader.damaged("a pair variable is for the particles (" + std::to_string(i) + ", " + std::to_string(j) +
                           "), not 0 <= i < j < " + std::to_string(n));
        return Key(i, j);
    };
    Saved saved;
    saved.inRangeStep = reader.take<int64_t>("the step of the pair variables");
    if (std::abs(saved.inRangeStep) > MAX_STEP_NUMBER)
        reader.damaged("the pair variables are of step " + std::to_string(saved.inRangeStep));
    for (uint64_t count = reader.takeCount("the number of pairs in range", 24); count > 0; count--) {
        const Key k = takeKey();
        const double s = reader.takeFinite("a pair variable"), wR2 = reader.takeFinite("a pair weight");
        if (wR2 < 0 || wR2 > 1)
            reader.damaged("a pair weight wR^2 is " + numberText(wR2) + ", outside [0, 1]");
        if (!saved.inRange.emplace(k, InRange{s, wR2}).second)
            reader.damaged("a pair in range is listed twice");
    }
    for (uint64_t count = reader.takeCount("the number of archived pairs", 24); count > 0; count--) {
        const Key k = takeKey();
        const double s = reader.takeFinite("a pair variable");
        const long long step = reader.take<int64_t>("the step of an archived pair");
        if (step > saved.inRangeStep || step < -MAX_STEP_NUMBER)
            reader.damaged("an archived pair variable is of step " + std::to_string(step) + ", after the pairs in range (" +
                           std::to_string(saved.inRangeStep) + ")");
        if (!saved.archived.emplace(k, Archived{s, step}).second)
            reader.damaged("an archived pair is listed twice");
    }
    if (saved.inRangeStep == -1 && !saved.inRange.empty())
        reader.damaged("pairs in range before the first step");
    return saved;
}

void ReferencePairMemory::restore(Saved&& saved) {
    inRangeStep = saved.inRangeStep;
    inRange.swap(saved.inRange);
    archived.swap(saved.archived);
}

void ReferencePairMemory::renumberSteps(long long step) {
    if (inRangeStep < 0 || inRangeStep == step)
        return;
    const long long shift = step - inRangeStep;
    for (auto& a : archived)
        a.second.step += shift;
    inRangeStep = step;
}

void ReferencePairMemory::clear() {
    inRangeStep = -1;
    inRange.clear();
    archived.clear();
}
