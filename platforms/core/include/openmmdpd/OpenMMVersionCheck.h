#ifndef OPENMMDPD_OPENMMVERSIONCHECK_H_
#define OPENMMDPD_OPENMMVERSIONCHECK_H_

#include <string>

namespace DPDPlugin {

/**
 * Empty if an OpenMM of version `running` can host plugins built against `built` (the same
 * major.minor), else why not.  Our kernels read OpenMM's platform data (positions,
 * velocities, thread pool), whose layout changes between minor versions (OpenMM 8.4 put a
 * ThreadPool before the positions), so a plugin built against another one reads wrong fields.
 */
std::string openmmVersionMismatch(const std::string& built, const std::string& running);

/**
 * Whether the running OpenMM (Platform::getOpenMMVersion()) is the major.minor this plugin was
 * built against (OPENMMDPD_OPENMM_VERSION); if not, says why on stderr, naming `plugin`,
 * and the caller registers nothing (OpenMM gives a plugin no other channel for errors).
 */
bool pluginMatchesRunningOpenMM(const std::string& plugin);

} // namespace DPDPlugin

#endif
