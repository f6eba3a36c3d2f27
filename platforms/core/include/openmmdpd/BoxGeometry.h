#ifndef OPENMMDPD_BOXGEOMETRY_H_
#define OPENMMDPD_BOXGEOMETRY_H_

#include "openmm/Vec3.h"

namespace DPDPlugin {

/**
 * Nearest integer, for |x| far below 2^63.  std::round is a library call on baseline
 * x86-64 and dominated the pair search; a truncating conversion is one instruction.
 */
inline double roundToInteger(double x) {
    return (double) (long long) (x + (x >= 0 ? 0.5 : -0.5));
}

/**
 * The rows of the inverse of OpenMM's upper-triangular box matrix [a b c]: fractional
 * coordinate k of r is rows[k] . r.  Both platforms bin particles into cells with it, so
 * that they find the same cells (and the sweeps the same pair order).
 */
inline void inverseBoxRows(const OpenMM::Vec3* box, OpenMM::Vec3* rows) {
    const OpenMM::Vec3 &a = box[0], &b = box[1], &c = box[2];
    rows[0] = OpenMM::Vec3(1 / a[0], -b[0] / (a[0] * b[1]), (b[0] * c[1] / b[1] - c[0]) / (a[0] * c[2]));
    rows[1] = OpenMM::Vec3(0, 1 / b[1], -c[1] / (b[1] * c[2]));
    rows[2] = OpenMM::Vec3(0, 0, 1 / c[2]);
}

} // namespace DPDPlugin

#endif
