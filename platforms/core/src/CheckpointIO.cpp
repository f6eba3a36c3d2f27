#include "openmmdpd/CheckpointIO.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <cstring>

using namespace DPDPlugin;

namespace {

const char MAGIC[8] = {'O', 'M', 'M', 'D', 'P', 'D', 'C', 'K'};
// Tags are short names; anything longer is not a header of ours.
const uint32_t MAX_TAG_LENGTH = 256;
// The payload is read in pieces so that a damaged size cannot make us allocate more than
// the stream actually holds.
const size_t READ_PIECE = 1 << 20;

[[noreturn]] void refuse(const std::string& name, const std::string& why) {
    throw OpenMM::OpenMMException(name + ": cannot load this checkpoint: " + why);
}

template <class T>
T readHeaderField(std::istream& stream, const std::string& name) {
    T value;
    stream.read((char*) &value, sizeof(T));
    if (!stream)
        refuse(name, "it ends inside the integrator's header (the file is truncated)");
    return value;
}

std::string readPayload(std::istream& stream, uint64_t size, const std::string& name) {
    std::string payload;
    while (payload.size() < size) {
        const size_t piece = (size_t) std::min<uint64_t>(READ_PIECE, size - payload.size());
        const size_t start = payload.size();
        payload.resize(start + piece);
        stream.read(&payload[start], piece);
        if (!stream)
            refuse(name, "it ends " + std::to_string(size - start - stream.gcount()) +
                             " bytes before the end of the integrator's data (the file is truncated)");
    }
    return payload;
}

} // namespace

void DPDPlugin::writeCheckpoint(std::ostream& stream, const std::string& tag, int numParticles, const std::string& payload) {
    stream.write(MAGIC, sizeof(MAGIC));
    putField<uint32_t>(stream, CHECKPOINT_FORMAT_VERSION);
    putField<uint32_t>(stream, tag.size());
    stream.write(tag.data(), tag.size());
    putField<int32_t>(stream, numParticles);
    putField<uint64_t>(stream, payload.size());
    stream.write(payload.data(), payload.size());
}

CheckpointReader DPDPlugin::readCheckpoint(std::istream& stream, const std::string& tag, int numParticles, const std::string& name) {
    char magic[sizeof(MAGIC)];
    stream.read(magic, sizeof(magic));
    if (!stream || std::memcmp(magic, MAGIC, sizeof(MAGIC)) != 0)
        refuse(name, "it has no openmm-dpd integrator header, so it was written by another integrator or by openmm-dpd "
                     "before checkpoint format 2. Start from a saved State (positions and velocities) instead");
    const uint32_t version = readHeaderField<uint32_t>(stream, name);
    if (version != CHECKPOINT_FORMAT_VERSION)
        refuse(name, "it is in checkpoint format " + std::to_string(version) + " and this build reads format " +
                         std::to_string(CHECKPOINT_FORMAT_VERSION));
    const uint32_t tagLength = readHeaderField<uint32_t>(stream, name);
    if (tagLength > MAX_TAG_LENGTH)
        refuse(name, "its integrator header is damaged (a name of " + std::to_string(tagLength) + " bytes)");
    std::string written(tagLength, ' ');
    stream.read(&written[0], tagLength);
    if (!stream)
        refuse(name, "it ends inside the integrator's header (the file is truncated)");
    if (written != tag)
        refuse(name, "it was written by a " + written + ", not by a " + tag);
    const int32_t particles = readHeaderField<int32_t>(stream, name);
    if (particles != numParticles)
        refuse(name, "it holds " + std::to_string(particles) + " particles and this System has " + std::to_string(numParticles));
    const uint64_t size = readHeaderField<uint64_t>(stream, name);
    return CheckpointReader(readPayload(stream, size, name), name);
}

void CheckpointReader::damaged(const std::string& what) const {
    throw OpenMM::OpenMMException(name + ": cannot load this checkpoint: it is damaged: " + what);
}

void CheckpointReader::takeBytes(void* destination, size_t bytes, const char* what) {
    if (payload.size() - offset < bytes)
        damaged(std::string("the integrator's data end inside ") + what);
    std::memcpy(destination, payload.data() + offset, bytes);
    offset += bytes;
}

double CheckpointReader::takeFinite(const char* what) {
    const double value = take<double>(what);
    if (!std::isfinite(value))
        damaged(std::string(what) + " is not finite");
    return value;
}

uint64_t CheckpointReader::takeCount(const char* what, size_t itemBytes) {
    const uint64_t count = take<uint64_t>(what);
    if (count > (payload.size() - offset) / itemBytes)
        damaged(std::string(what) + " is " + std::to_string(count) + ", more than the data hold");
    return count;
}

void CheckpointReader::takeVectors(std::vector<OpenMM::Vec3>& values, const char* what) {
    const uint64_t count = take<uint64_t>(what);
    if (count != values.size())
        damaged(std::string(what) + ": " + std::to_string(count) + " values where this System has " +
                std::to_string(values.size()));
    takeBytes(values.data(), values.size() * sizeof(OpenMM::Vec3), what);
    for (const OpenMM::Vec3& x : values)
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
            damaged(std::string(what) + " holds a value that is not finite");
}

void CheckpointReader::expectEnd() const {
    if (offset != payload.size())
        damaged(std::to_string(payload.size() - offset) + " bytes follow the integrator's data");
}
