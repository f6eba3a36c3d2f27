#ifndef OPENMMDPD_PARAMETERCHECKS_H_
#define OPENMMDPD_PARAMETERCHECKS_H_

#include "openmm/OpenMMException.h"
#include <sstream>
#include <string>

namespace DPDPlugin {

/** Throw an OpenMMException with this message unless ok (checks run before anything changes). */
inline void require(bool ok, const std::string& message) {
    if (!ok)
        throw OpenMM::OpenMMException(message);
}

/** A number as it reads in an error message. */
inline std::string numberText(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

} // namespace DPDPlugin

#endif
