#include "openmmdpd/OpenMMVersionCheck.h"
#include "openmm/Platform.h"
#include <iostream>

namespace DPDPlugin {

namespace {

/** "8.5" of "8.5.2", "7.7" of "7.7". */
std::string majorMinor(const std::string& version) {
    const size_t first = version.find('.');
    return first == std::string::npos ? version : version.substr(0, version.find('.', first + 1));
}

} // namespace

std::string openmmVersionMismatch(const std::string& built, const std::string& running) {
    if (majorMinor(built) == majorMinor(running))
        return "";
    return "built against OpenMM " + majorMinor(built) + " but loaded into OpenMM " + running +
           ", whose internal platform data may be laid out differently; rebuild openmm-dpd against OpenMM " +
           majorMinor(running) + " (cmake -DOPENMM_DIR=<its prefix>)";
}

bool pluginMatchesRunningOpenMM(const std::string& plugin) {
    const std::string why = openmmVersionMismatch(OPENMMDPD_OPENMM_VERSION, OpenMM::Platform::getOpenMMVersion());
    if (!why.empty())
        std::cerr << plugin << ": not registering its kernels: " << why << std::endl;
    return why.empty();
}

} // namespace DPDPlugin
