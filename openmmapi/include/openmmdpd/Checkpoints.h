#ifndef OPENMMDPD_CHECKPOINTS_H_
#define OPENMMDPD_CHECKPOINTS_H_

#include "openmm/Context.h"
#include <istream>

namespace DPDPlugin {

/**
 * Load a checkpoint into a Context, as Context::loadCheckpoint() does, except that a
 * checkpoint that is refused leaves the Context exactly as it was before the call: its
 * positions, velocities, time, step count, box, parameters and the integrator's state, bit
 * for bit.  (Context::loadCheckpoint() restores OpenMM's part of a checkpoint before the
 * integrator reads its own, so after a refusal there the Context holds the refused file's
 * positions and velocities, and the integrator re-derives its state from them.)
 *
 * The error of a refusal is an OpenMMException whose message is printable text whatever
 * the file held.
 *
 * @param context  the Context to load into (any integrator)
 * @param stream   the checkpoint, as Context::createCheckpoint() wrote it
 */
void loadCheckpoint(OpenMM::Context& context, std::istream& stream);

} // namespace DPDPlugin

#endif
