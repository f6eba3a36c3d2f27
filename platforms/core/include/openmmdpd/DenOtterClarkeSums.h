#ifndef OPENMMDPD_DENOTTERCLARKESUMS_H_
#define OPENMMDPD_DENOTTERCLARKESUMS_H_

#include "openmmdpd/PairParameters.h"
#include "openmm/Vec3.h"

namespace DPDPlugin {

/**
 * The running sums of DenOtterClarkeIntegrator::getMeasuredSums, which either platform's
 * den Otter-Clarke step adds to: FD_i . v_i, FD_i . FD_i and FR_i . FR_i with FR without
 * 1/sqrt(dt), over steps and particles with mass.
 */
struct DenOtterClarkeSums {
    double fdDotV = 0, fdDotFD = 0, frDotFR = 0;
    long long count = 0;
    /** One particle's terms, from FR with its 1/sqrt(dt) (so FR . FR dt is added). */
    void add(const OpenMM::Vec3& fd, const OpenMM::Vec3& fr, const OpenMM::Vec3& v, double dt) {
        fdDotV += fd.dot(v);
        fdDotFD += fd.dot(fd);
        frDotFR += fr.dot(fr) * dt;
        count++;
    }
    void add(const DenOtterClarkeSums& other) {
        fdDotV += other.fdDotV;
        fdDotFD += other.fdDotFD;
        frDotFR += other.frDotFR;
        count += other.count;
    }
    void get(double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR, long long& terms) const {
        sumFDDotV = fdDotV;
        sumFDDotFD = fdDotFD;
        sumFRDotFR = frDotFR;
        terms = count;
    }
    /** The mass m of eq. 7: that of every particle with mass (DenOtterClarkeIntegrator::validate requires one). */
    static double thermostatMass(const DPDPairParameters& parameters) {
        for (int i = 0; i < parameters.getNumParticles(); i++)
            if (parameters.getActive()[i])
                return parameters.getMasses()[i];
        return 1;  // no particle moves: any mass will do
    }
};

} // namespace DPDPlugin

#endif
