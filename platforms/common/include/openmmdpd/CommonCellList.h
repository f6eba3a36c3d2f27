#ifndef OPENMMDPD_COMMONCELLLIST_H_
#define OPENMMDPD_COMMONCELLLIST_H_

#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/common/ComputeKernel.h"
#include "openmm/common/ComputeProgram.h"
#include "openmm/Vec3.h"
#include <array>
#include <initializer_list>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * Each cell's start from the cells' counts, on the device (kernels/cellList.cc): a prefix
 * sum in parallel, over blocks of BlockSize cells (one work group each), then over the
 * blocks' totals.  Integer sums: the same starts as a sequential loop.
 */
class CommonCellScan {
public:
    static const int BlockSize = 128;
    /** @param program  a program compiled with kernels/cellList.cc */
    CommonCellScan(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram program);
    /** cellStart[c] = the sum of cellCount below c (cellStart[numCells] = the total); cellCount is zeroed. */
    void execute(int numCells, OpenMM::ComputeArray& cellCount, OpenMM::ComputeArray& cellStart);

private:
    OpenMM::ComputeContext& cc;
    OpenMM::ComputeKernel blockKernel, sumsKernel, addKernel;
    OpenMM::ComputeArray blockSums;
};

/**
 * The box as the kernels take it (kernels/utilities.cc, cellList.cc).  A periodic box of
 * OpenMM's reduced form: size = (Lx, Ly, Lz, b's tilt along x), inverse = (1/Lx, 1/Ly, 1/Lz, 0),
 * c = the third vector, and the rows of the inverse box matrix that bin positions in
 * fractional coordinates, rowX = rows[0] and rowYZ = (rows[1][1], rows[1][2], rows[2][2], 0),
 * from origin 0.  An open System's grid (open()): the particles' bounding box as the rows and
 * origin, and size, inverse and c all 0, which leaves every pair at its own displacement.
 */
struct DeviceBox {
    DeviceBox() = default;
    explicit DeviceBox(const OpenMM::Vec3* box);
    /** The grid over [lo, lo + extent) along each axis, with no periodic images. */
    static DeviceBox open(const OpenMM::Vec3& lo, const OpenMM::Vec3& extent);
    /** The cells along axis k at least `width` wide across, at most MaxCellsAcross. */
    int cellsAcross(int k, double width) const;
    static constexpr int MaxCellsAcross = 1 << 20;
    OpenMM::Vec3 rows[3];
    double size[4] = {}, inverse[4] = {}, c[4] = {}, rowX[4] = {}, rowYZ[4] = {}, origin[4] = {};
};

/**
 * The box a grid is built in, at the current positions: the Context's periodic box, or in an
 * open System, as the Reference takes it (ReferencePairList::bin), the bounding box of the
 * particles (those that move, 1/m != 0, if movingOnly), found on the device and read back,
 * at least the cutoff wide along each axis.
 */
class CommonGridBox {
public:
    /** @param program  a program compiled with kernels/cellList.cc; owner names the caller in errors */
    CommonGridBox(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram program, const std::string& owner, bool periodic,
                  bool movingOnly);
    bool isPeriodic() const { return periodic; }
    /** Refuses (OpenMMException) a periodic box too small for `cutoff`, which `what` names. */
    DeviceBox current(double cutoff, const std::string& what);

private:
    DeviceBox openGrid(double cutoff);
    static constexpr int Slots = 1024;  // the particles' shares, each bounded by one work item
    OpenMM::ComputeContext& cc;
    std::string owner;
    bool periodic, movingOnly;
    OpenMM::ComputeKernel kernel;  // an open System's
    OpenMM::ComputeArray bounds;
};

/**
 * A cell list on the device (kernels/cellList.cc), rebuilt at the current positions before
 * every pair pass: cells at least the cutoff wide across, on the fractional axes of any
 * periodic box of OpenMM's reduced form (rectangular, sheared or triclinic), or of an open
 * System's bounding box.  A pair kernel
 * takes its NUM_ARGS arguments (box size, inverse box size, the box's c, cell counts, each
 * slot's cell, cell starts, slots by cell), set by setArgs.
 */
class CommonCellList {
public:
    static constexpr int NUM_ARGS = 7;
    /**
     * @param program         a program compiled with kernels/cellList.cc
     * @param owner           names the caller in errors
     * @param periodic        the periodic box, or an open System's bounding box
     * @param boundsOfMoving  in an open System, the bounding box of the particles that move
     *                        only (a thermostat's: the others take no part in its pairs)
     */
    CommonCellList(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram program, const std::string& owner, bool periodic,
                   bool boundsOfMoving = false);
    /** Refuses (OpenMMException) a periodic box too small for the cutoff. */
    void build(double cutoff);
    /** Set the cell-list arguments of a pair kernel, from argument index `first` on. */
    void setArgs(OpenMM::ComputeKernel& kernel, int first);

private:
    OpenMM::ComputeContext& cc;
    std::string owner;
    OpenMM::ComputeKernel clearKernel, assignKernel, fillKernel;
    CommonCellScan scan;
    CommonGridBox grid;
    OpenMM::ComputeArray atomCell, cellCount, cellStart, cellAtoms;
    DeviceBox box;
    int numCells[3], totalCells = 0;
};

/** The kernel `name` of `program` with `args` arguments, each to be set before it runs. */
OpenMM::ComputeKernel createKernelWithArgs(OpenMM::ComputeProgram& program, const std::string& name, int args);
/** Add array arguments to a kernel, in order. */
void addArrayArgs(OpenMM::ComputeKernel& kernel, std::initializer_list<OpenMM::ArrayInterface*> arrays);
/** Set array arguments of a kernel, from index `first` on. */
void setArrayArgs(OpenMM::ComputeKernel& kernel, int first, std::initializer_list<OpenMM::ArrayInterface*> arrays);
/** Add a `mixed` scalar (double or float, as the context's precision says) to a kernel. */
void addMixedArg(OpenMM::ComputeContext& cc, OpenMM::ComputeKernel& kernel, double value);
void setMixedArg(OpenMM::ComputeContext& cc, OpenMM::ComputeKernel& kernel, int index, double value);
/** Set a `mixed4` argument. */
void setMixed4Arg(OpenMM::ComputeContext& cc, OpenMM::ComputeKernel& kernel, int index, const double value[4]);
/** Fill a `mixed` array, or an int array, from values (one 0 if there are none: an array is never empty). */
void uploadMixed(OpenMM::ComputeContext& cc, OpenMM::ComputeArray& array, const std::vector<double>& values, const std::string& name);
void uploadInts(OpenMM::ComputeContext& cc, OpenMM::ComputeArray& array, const std::vector<int>& values, const std::string& name);
/**
 * Fill start (numAtoms + 1 ints) and partners with each atom's partners in `pairs` (both
 * ways, by atom index): atom a's are partners[start[a], start[a+1]).
 */
void uploadPartnerLists(OpenMM::ComputeContext& cc, int numAtoms, const std::vector<std::pair<int, int>>& pairs, OpenMM::ComputeArray& start,
                        OpenMM::ComputeArray& partners, const std::string& name);
/** Fill a `mixed4` array from (x, y, z, w) rows. */
void uploadMixed4(OpenMM::ComputeContext& cc, OpenMM::ComputeArray& array, const std::vector<double>& rows, const std::string& name);
/** The values of a `mixed` array, as doubles. */
std::vector<double> downloadMixed(OpenMM::ComputeContext& cc, OpenMM::ComputeArray& array);
/** The sum over `threads` work items of their virial rows (component c of item k at k + c threads), in double precision. */
std::array<double, 6> sumVirialRows(OpenMM::ComputeContext& cc, OpenMM::ComputeArray& rows, int threads);
/** The `mixed` type is double under double or mixed precision. */
bool mixedIsDouble(OpenMM::ComputeContext& cc);
/** Compile kernels/utilities.cc followed by `sources`, with this plugin's defines. */
OpenMM::ComputeProgram compileDPDProgram(OpenMM::ComputeContext& cc, const std::vector<std::string>& sources);

} // namespace DPDPlugin

#endif
