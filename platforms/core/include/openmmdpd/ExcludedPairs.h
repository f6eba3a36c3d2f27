#ifndef OPENMMDPD_EXCLUDEDPAIRS_H_
#define OPENMMDPD_EXCLUDEDPAIRS_H_

#include <algorithm>
#include <utility>
#include <vector>

namespace DPDPlugin {

/** A force's exclusions (getNumExclusions, getExclusionParticles: DPDSoftRepulsionForce, MDPDForce) as particle pairs. */
template <class Force>
std::vector<std::pair<int, int>> exclusionPairs(const Force& force) {
    std::vector<std::pair<int, int>> pairs(force.getNumExclusions());
    for (int k = 0; k < force.getNumExclusions(); k++)
        force.getExclusionParticles(k, pairs[k].first, pairs[k].second);
    return pairs;
}

/** Each particle's excluded partners, sorted: what a pair loop looks a pair up in. */
class ExcludedPairs {
public:
    ExcludedPairs() = default;
    ExcludedPairs(int numParticles, const std::vector<std::pair<int, int>>& pairs) : partners(numParticles), any(!pairs.empty()) {
        for (const std::pair<int, int>& pair : pairs) {
            partners[pair.first].push_back(pair.second);
            partners[pair.second].push_back(pair.first);
        }
        for (std::vector<int>& list : partners)
            std::sort(list.begin(), list.end());
    }
    bool empty() const { return !any; }
    bool contains(int i, int j) const {
        if (!any)
            return false;
        const std::vector<int>& list = partners[i];
        return !list.empty() && std::binary_search(list.begin(), list.end(), j);
    }

private:
    std::vector<std::vector<int>> partners;
    bool any = false;
};

} // namespace DPDPlugin

#endif
