#ifndef OPENMMDPD_CHECKPOINTIO_H_
#define OPENMMDPD_CHECKPOINTIO_H_

#include "openmm/Vec3.h"
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace DPDPlugin {

/*
 * The integrator part of this plugin's checkpoints, written and read in one place for
 * every platform and integrator.  Binary, so that a continuation is bit-exact:
 *
 *   magic "OMMDPDCK", format version (uint32), the length of OpenMM's part before it (uint64;
 *   0 where the stream could not be read back), integrator tag (uint32 length + chars: the
 *   class and its variant), particle count (int32), payload size (uint64), payload, checksum.
 *
 * The checksum (XXH3, 64 bits) covers every byte before it: OpenMM's part of the checkpoint
 * (positions, velocities, time, box, parameters) as far as its length says, then ours.  It
 * is checked, and nothing may follow it, before any field is used; then every field is still
 * checked (sizes against what is left, indices, finiteness), so that a damaged or foreign
 * checkpoint is refused with an OpenMMException before any integrator state changes.
 * OpenMM restores its own part before ours is read: a refused checkpoint has changed the
 * Context by then, which loadCheckpoint (openmmdpd/Checkpoints.h) undoes.
 */

/** The format this version writes; earlier ones (1: no header, 2: no checksum) are refused. */
constexpr uint32_t CHECKPOINT_FORMAT_VERSION = 3;

/** Step numbers read from a checkpoint lie within +-MAX_STEP_NUMBER, so differences of two cannot overflow. */
constexpr long long MAX_STEP_NUMBER = 1LL << 62;

template <class T>
void putField(std::ostream& stream, const T& value) {
    stream.write((const char*) &value, sizeof(T));
}

/** A count, then the vectors. */
inline void putVectors(std::ostream& stream, const std::vector<OpenMM::Vec3>& values) {
    putField<uint64_t>(stream, values.size());
    stream.write((const char*) values.data(), values.size() * sizeof(OpenMM::Vec3));
}

/** The header, then the payload. */
void writeCheckpoint(std::ostream& stream, const std::string& tag, int numParticles, const std::string& payload);

/**
 * The fields of a payload, taken in order.  Every error names the integrator (`name`) and
 * says what was wrong, e.g. "DPDVVIntegrator: the checkpoint is damaged: ...".
 */
class CheckpointReader {
public:
    CheckpointReader(std::string payload, std::string name) : payload(std::move(payload)), name(std::move(name)) {}
    template <class T>
    T take(const char* what) {
        T value;
        takeBytes(&value, sizeof(T), what);
        return value;
    }
    /** A finite double. */
    double takeFinite(const char* what);
    /** A count of items of itemBytes bytes each that must fit in what is left. */
    uint64_t takeCount(const char* what, size_t itemBytes);
    /** What putVectors wrote, into `values`, which must already have the size written; all finite. */
    void takeVectors(std::vector<OpenMM::Vec3>& values, const char* what);
    /** Every byte of the payload must have been taken. */
    void expectEnd() const;
    /** Throws "<name>: the checkpoint is damaged: <what>". */
    [[noreturn]] void damaged(const std::string& what) const;

private:
    void takeBytes(void* destination, size_t bytes, const char* what);
    std::string payload;
    size_t offset = 0;
    std::string name;
};

/**
 * Reads the header and the payload written by writeCheckpoint, refusing a checkpoint that
 * is not this plugin's, of another format, another integrator (tag) or particle count.
 * `name` (the integrator class) prefixes the errors.
 */
CheckpointReader readCheckpoint(std::istream& stream, const std::string& tag, int numParticles, const std::string& name);

/**
 * Refuses a whole checkpoint (OpenMM's part and ours, as Context::createCheckpoint() wrote
 * them) whose integrator part is missing, damaged or followed by other bytes, before OpenMM
 * reads any of it: OpenMM trusts the sizes in its own part, and a damaged one can make it
 * allocate without bound.  Foreign tags and particle counts are left to the integrator.
 */
void requireIntactCheckpoint(const std::string& checkpoint, const std::string& name);

} // namespace DPDPlugin

#endif
