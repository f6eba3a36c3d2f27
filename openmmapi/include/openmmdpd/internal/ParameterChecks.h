#ifndef OPENMMDPD_PARAMETERCHECKS_H_
#define OPENMMDPD_PARAMETERCHECKS_H_

#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <charconv>
#include <string>

/*
 * Every error message of the plugin reads "ClassName: parameter must be ..., got X", with X
 * printed as the user wrote it.
 */

namespace DPDPlugin {

/** Throw an OpenMMException with this message unless ok (checks run before anything changes). */
inline void require(bool ok, const std::string& message) {
    if (!ok)
        throw OpenMM::OpenMMException(message);
}

/** A number as it reads in an error message: the shortest text that reads back as x (1.2, not 1.200000). */
inline std::string numberText(double x) {
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof(text), x).ptr);
}

/**
 * Text taken from a file, made fit for an error message: bytes outside printable ASCII become
 * \xNN, so a damaged file cannot make the message invalid UTF-8 (Python shows such a message
 * as empty).
 */
inline std::string printable(const std::string& text) {
    static const char* hex = "0123456789abcdef";
    std::string result;
    for (unsigned char c : text) {
        if (c >= 0x20 && c < 0x7f && c != '\\')
            result += (char) c;
        else
            result += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    }
    return result;
}

/**
 * Throw unless a cutoff (nm) is at most half the smallest width of an OpenMM periodic box
 * (reduced form, so the widths are the diagonal), which the pair searches need.
 */
inline void requireCutoffFitsBox(const std::string& owner, const std::string& what, double cutoff, const OpenMM::Vec3* box) {
    const double halfWidth = 0.5 * std::min(box[0][0], std::min(box[1][1], box[2][2]));
    require(cutoff <= halfWidth, owner + ": " + what + " must be <= half the periodic box width (" + numberText(halfWidth) +
            " nm), got " + numberText(cutoff) + " nm");
}

} // namespace DPDPlugin

#endif
