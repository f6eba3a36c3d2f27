#ifndef OPENMMDPD_LEESEDWARDSBOUNDARY_H_
#define OPENMMDPD_LEESEDWARDSBOUNDARY_H_

#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include <vector>

namespace DPDPlugin {

/**
 * The sliding boundaries of Lees-Edwards shear (docs/theory/lees-edwards.md), for every update
 * rule of every platform that keeps its state in the Reference platform's data.  The
 * sliding image is the Context's triclinic box b = (offset, Ly, 0); after each drift of
 * duration dt the offset advances by U dt (U = rate Ly) and every molecule (findMolecules:
 * the particles joined by any bonded term, constraint or virtual site) whose centre has left 0 <= y < Ly is brought
 * back by whole box heights, n b, with its x velocity lowered by n U.  The pairs across the
 * boundary see their partner's image moving (DPDPairParameters::imageVelocityX).
 */
class LeesEdwardsBoundary {
public:
    /**
     * The box after a drift of duration dt at shear rate `rate`: b's offset advanced by U dt
     * (U = rate Ly, returned) and brought back to OpenMM's reduced form, |offset| <= Lx/2
     * (b and b - a give the same lattice).  Every platform slides its box by it.
     */
    static double advanceOffset(OpenMM::Vec3* box, double rate, double dt);
    explicit LeesEdwardsBoundary(const OpenMM::System& system);
    /**
     * After a drift of duration dt at shear rate `rate` (nothing if 0): slide the box, wrap
     * the molecules, and give the velocities (and `alsoJump`, velocities carried beside
     * them, if given) the jumps of the molecules that crossed.
     */
    void slide(OpenMM::ContextImpl& context, double rate, double dt, std::vector<OpenMM::Vec3>& positions,
               std::vector<OpenMM::Vec3>& velocities, std::vector<OpenMM::Vec3>* alsoJump = nullptr) const;

private:
    /** Particle i crossed the boundary `crossings` times: back by that many b, its x velocity (if it moves) by that many U. */
    void wrap(int i, double crossings, const OpenMM::Vec3& b, double U, std::vector<OpenMM::Vec3>& positions,
              std::vector<OpenMM::Vec3>& velocities, std::vector<OpenMM::Vec3>* alsoJump) const;
    std::vector<bool> moves;  // mass > 0: its velocity takes the jump
    std::vector<std::vector<int>> molecules;
};

} // namespace DPDPlugin

#endif
