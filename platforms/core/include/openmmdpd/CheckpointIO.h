#ifndef OPENMMDPD_CHECKPOINTIO_H_
#define OPENMMDPD_CHECKPOINTIO_H_

#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace DPDPlugin {

/*
 * The binary fields of this plugin's checkpoints, written and read in one place for every
 * platform: binary so that a continuation is bit-exact.
 */

template <class T>
void putField(std::ostream& stream, const T& value) {
    stream.write((const char*) &value, sizeof(T));
}

/** A field of type T; `name` prefixes the error if the stream ends first. */
template <class T>
T takeField(std::istream& stream, const std::string& name) {
    T value;
    stream.read((char*) &value, sizeof(T));
    if (!stream)
        throw OpenMM::OpenMMException(name + ": the checkpoint is truncated");
    return value;
}

/** A count, then the vectors. */
inline void putVectors(std::ostream& stream, const std::vector<OpenMM::Vec3>& values) {
    putField<uint64_t>(stream, values.size());
    stream.write((const char*) values.data(), values.size() * sizeof(OpenMM::Vec3));
}

/** Reads what putVectors wrote into `values`, which must already have the size written. */
inline void takeVectors(std::istream& stream, std::vector<OpenMM::Vec3>& values, const std::string& name, const std::string& what) {
    if (takeField<uint64_t>(stream, name) != values.size())
        throw OpenMM::OpenMMException(name + ": the checkpoint does not match this System's " + what);
    stream.read((char*) values.data(), values.size() * sizeof(OpenMM::Vec3));
    if (!stream)
        throw OpenMM::OpenMMException(name + ": the checkpoint is truncated");
}

} // namespace DPDPlugin

#endif
