#ifndef OPENMMDPD_REFERENCEPOSITIONSTRAIN_H_
#define OPENMMDPD_REFERENCEPOSITIONSTRAIN_H_

#include "openmmdpd/PressureTensor.h"
#include "ReferencePlatform.h"
#include <vector>

namespace DPDPlugin {

/** PositionStrain in the positions the Reference and CPU platforms store (their shared platform data). */
class ReferencePositionStrain : public PositionStrain {
public:
    void strain(OpenMM::ContextImpl& context, int a, int b, double strain) override {
        std::vector<OpenMM::Vec3>& r = positions(context);
        if (original.empty())
            original = r;
        for (size_t i = 0; i < r.size(); i++) {
            r[i] = original[i];
            r[i][a] += strain * original[i][b];
        }
    }
    void restore(OpenMM::ContextImpl& context) override {
        if (!original.empty())
            positions(context) = original;
        original.clear();
    }
    void setBox(OpenMM::ContextImpl& context, const OpenMM::Vec3* box) override {
        context.setPeriodicBoxVectors(box[0], box[1], box[2]);
    }

private:
    static std::vector<OpenMM::Vec3>& positions(OpenMM::ContextImpl& context) {
        return *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData())->positions;
    }
    std::vector<OpenMM::Vec3> original;
};

} // namespace DPDPlugin

#endif
