#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
// Header-only: the checksum needs no library at run time.
#define XXH_INLINE_ALL
#include <xxhash.h>

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

/** What the stream holds before the integrator's part (OpenMM's part), where it can be read back. */
std::string writtenBefore(std::ostream& stream) {
    auto* buffer = dynamic_cast<std::stringbuf*>(stream.rdbuf());
    const std::streamoff end = stream.tellp();
    if (buffer == nullptr || end <= 0)
        return std::string();
    return buffer->str().substr(0, (size_t) end);
}

template <class T>
void append(std::string& bytes, const T& value) {
    bytes.append((const char*) &value, sizeof(T));
}

uint64_t checksum(const std::string& before, const std::string& part) {
    XXH3_state_t* state = XXH3_createState();
    XXH3_64bits_reset(state);
    XXH3_64bits_update(state, before.data(), before.size());
    XXH3_64bits_update(state, part.data(), part.size());
    const uint64_t digest = XXH3_64bits_digest(state);
    XXH3_freeState(state);
    return digest;
}

/** Reads the integrator's part, keeping every byte read for the checksum. */
class PartReader {
public:
    PartReader(std::istream& stream, const std::string& name) : stream(stream), name(name) {}
    template <class T>
    T field() {
        T value;
        bytes(sizeof(T), (char*) &value);
        return value;
    }
    /** n bytes, read in pieces (n may be damaged: we never allocate more than the stream holds). */
    std::string text(uint64_t n) {
        std::string result;
        while (result.size() < n) {
            const size_t piece = (size_t) std::min<uint64_t>(READ_PIECE, n - result.size());
            const size_t start = result.size();
            result.resize(start + piece);
            bytes(piece, &result[start]);
        }
        return result;
    }
    std::string read;  // every byte so far

private:
    void bytes(size_t n, char* destination) {
        stream.read(destination, n);
        if ((size_t) stream.gcount() != n)
            refuse(name, "it ends inside the integrator's data (the file is truncated)");
        read.append(destination, n);
    }
    std::istream& stream;
    const std::string& name;
};

/** The `length` bytes before the integrator's part, which began at `start`; the stream is left where it was. */
std::string readBefore(std::istream& stream, std::streamoff start, uint64_t length, const std::string& name) {
    if (length == 0)
        return std::string();
    if (start < 0 || (uint64_t) start < length)
        refuse(name, "it is damaged: its checksum covers " + std::to_string(length) + " bytes before the integrator's "
                     "data, and the stream holds " + std::to_string(std::max<std::streamoff>(start, 0)) +
                     " (or cannot be read back: load the checkpoint from a file or from bytes)");
    const std::streampos end = stream.tellg();
    std::string before((size_t) length, '\0');
    stream.seekg(start - (std::streamoff) length);
    stream.read(&before[0], (std::streamsize) length);
    if (!stream)
        refuse(name, "the bytes before the integrator's data, which its checksum covers, cannot be read back");
    stream.seekg(end);
    return before;
}

} // namespace

void DPDPlugin::writeCheckpoint(std::ostream& stream, const std::string& tag, int numParticles, const std::string& payload) {
    const std::string before = writtenBefore(stream);
    std::string part(MAGIC, sizeof(MAGIC));
    append<uint32_t>(part, CHECKPOINT_FORMAT_VERSION);
    append<uint64_t>(part, before.size());
    append<uint32_t>(part, tag.size());
    part += tag;
    append<int32_t>(part, numParticles);
    append<uint64_t>(part, payload.size());
    part += payload;
    append<uint64_t>(part, checksum(before, part));
    stream.write(part.data(), part.size());
}

namespace {

/** The integrator's part as written, its checksum and that nothing follows it checked. */
struct IntegratorPart {
    std::string tag;
    int32_t particles;
    std::string payload;
};

IntegratorPart readIntegratorPart(std::istream& stream, const std::string& name) {
    const std::streamoff start = stream.tellg();
    PartReader in(stream, name);
    char magic[sizeof(MAGIC)];
    stream.read(magic, sizeof(magic));
    if ((size_t) stream.gcount() != sizeof(MAGIC) || std::memcmp(magic, MAGIC, sizeof(MAGIC)) != 0)
        refuse(name, "it has no openmm-dpd integrator header, so it was written by another integrator or by openmm-dpd "
                     "before checkpoint format 2, or it is damaged. Start from a saved State (positions and velocities) instead");
    in.read.assign(magic, sizeof(magic));
    const uint32_t version = in.field<uint32_t>();
    if (version != CHECKPOINT_FORMAT_VERSION)
        refuse(name, "it is in checkpoint format " + std::to_string(version) + " and this build reads format " +
                         std::to_string(CHECKPOINT_FORMAT_VERSION) + " (or the file is damaged)");
    const uint64_t beforeLength = in.field<uint64_t>();
    const uint32_t tagLength = in.field<uint32_t>();
    if (tagLength > MAX_TAG_LENGTH)
        refuse(name, "it is damaged: its integrator header gives a name of " + std::to_string(tagLength) + " bytes");
    IntegratorPart part;
    part.tag = in.text(tagLength);
    part.particles = in.field<int32_t>();
    const uint64_t size = in.field<uint64_t>();
    part.payload = in.text(size);
    const std::string bytes = in.read;
    const uint64_t expected = in.field<uint64_t>();
    if (checksum(readBefore(stream, start, beforeLength, name), bytes) != expected)
        refuse(name, "it is damaged: its checksum does not match its contents (it was changed after it was written)");
    if (stream.peek() != std::char_traits<char>::eof())
        refuse(name, "bytes follow its end (it was changed after it was written)");
    return part;
}

} // namespace

CheckpointReader DPDPlugin::readCheckpoint(std::istream& stream, const std::string& tag, int numParticles, const std::string& name) {
    IntegratorPart part = readIntegratorPart(stream, name);
    if (part.tag != tag)
        refuse(name, "it was written by a " + printable(part.tag) + ", not by a " + tag);
    if (part.particles != numParticles)
        refuse(name, "it holds " + std::to_string(part.particles) + " particles and this System has " +
                         std::to_string(numParticles));
    return CheckpointReader(std::move(part.payload), name);
}

void DPDPlugin::requireIntactCheckpoint(const std::string& checkpoint, const std::string& name) {
    // The integrator's part ends the checkpoint, so its header is the last copy of the magic.
    const size_t begin = checkpoint.rfind(std::string(MAGIC, sizeof(MAGIC)));
    std::istringstream stream(checkpoint);
    stream.seekg(begin == std::string::npos ? checkpoint.size() : begin);
    readIntegratorPart(stream, name);
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
