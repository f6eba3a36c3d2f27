#include "openmmdpd/CommonCellList.h"
#include "CommonDPDKernelSources.h"
#include "openmmdpd/BoxGeometry.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ComputeVectorTypes.h"
#include <algorithm>
#include <cmath>

using namespace DPDPlugin;
using namespace OpenMM;

bool DPDPlugin::mixedIsDouble(ComputeContext& cc) {
    return cc.getUseDoublePrecision() || cc.getUseMixedPrecision();
}

ComputeProgram DPDPlugin::compileDPDProgram(ComputeContext& cc, const std::vector<std::string>& sources) {
    // The pair formulas first: written once for host and device (PairFormulas.h).
    std::string source = CommonDPDKernelSources::pairFormulas + CommonDPDKernelSources::utilities;
    for (const std::string& s : sources)
        source += s;
    std::map<std::string, std::string> defines;
    defines["OPENMMDPD_DEVICE_CODE"] = "1";
    if (cc.getUseMixedPrecision())
        defines["OPENMMDPD_MIXED"] = "1";
    // 2 pi as a literal of the `mixed` type (a double literal would need fp64 in single precision).
    defines["TWO_PI"] = mixedIsDouble(cc) ? "6.283185307179586" : "6.2831853f";
    defines["CELL_SCAN_BLOCK"] = std::to_string(CommonCellScan::BlockSize);
    return cc.compileProgram(source, defines);
}

void DPDPlugin::addArrayArgs(ComputeKernel& kernel, std::initializer_list<ArrayInterface*> arrays) {
    for (ArrayInterface* a : arrays)
        kernel->addArg(*a);
}

void DPDPlugin::setArrayArgs(ComputeKernel& kernel, int first, std::initializer_list<ArrayInterface*> arrays) {
    for (ArrayInterface* a : arrays)
        kernel->setArg(first++, *a);
}

void DPDPlugin::addMixedArg(ComputeContext& cc, ComputeKernel& kernel, double value) {
    if (mixedIsDouble(cc))
        kernel->addArg(value);
    else
        kernel->addArg((float) value);
}

ComputeKernel DPDPlugin::createKernelWithArgs(ComputeProgram& program, const std::string& name, int args) {
    ComputeKernel kernel = program->createKernel(name);
    for (int a = 0; a < args; a++)
        kernel->addArg();
    return kernel;
}

void DPDPlugin::setMixedArg(ComputeContext& cc, ComputeKernel& kernel, int index, double value) {
    if (mixedIsDouble(cc))
        kernel->setArg(index, value);
    else
        kernel->setArg(index, (float) value);
}

void DPDPlugin::setMixed4Arg(ComputeContext& cc, ComputeKernel& kernel, int index, const double v[4]) {
    if (mixedIsDouble(cc))
        kernel->setArg(index, mm_double4(v[0], v[1], v[2], v[3]));
    else
        kernel->setArg(index, mm_float4((float) v[0], (float) v[1], (float) v[2], (float) v[3]));
}

namespace {

template <class T>
void uploadResized(ComputeContext& cc, ComputeArray& array, const std::vector<T>& data, const std::string& name) {
    if (!array.isInitialized())
        array.initialize<T>(cc, data.size(), name);
    else if ((size_t) array.getSize() != data.size())
        array.resize(data.size());
    array.upload(data);
}

} // namespace

void DPDPlugin::uploadMixed(ComputeContext& cc, ComputeArray& array, const std::vector<double>& values, const std::string& name) {
    const std::vector<double> padded = values.empty() ? std::vector<double>(1, 0.0) : values;
    if (mixedIsDouble(cc))
        uploadResized(cc, array, padded, name);
    else
        uploadResized(cc, array, std::vector<float>(padded.begin(), padded.end()), name);
}

std::array<double, 6> DPDPlugin::sumVirialRows(ComputeContext& cc, ComputeArray& rows, int threads) {
    const std::vector<double> values = downloadMixed(cc, rows);
    std::array<double, 6> virial{};
    for (int c = 0; c < 6; c++)
        for (int k = 0; k < threads; k++)
            virial[c] += values[k + c * threads];
    return virial;
}

std::vector<double> DPDPlugin::downloadMixed(ComputeContext& cc, ComputeArray& array) {
    if (mixedIsDouble(cc)) {
        std::vector<double> values;
        array.download(values);
        return values;
    }
    std::vector<float> values;
    array.download(values);
    return std::vector<double>(values.begin(), values.end());
}

void DPDPlugin::uploadInts(ComputeContext& cc, ComputeArray& array, const std::vector<int>& values, const std::string& name) {
    uploadResized(cc, array, values.empty() ? std::vector<int>(1, 0) : values, name);
}

void DPDPlugin::uploadPartnerLists(ComputeContext& cc, int numAtoms, const std::vector<std::pair<int, int>>& pairs, ComputeArray& start,
                                   ComputeArray& partners, const std::string& name) {
    std::vector<std::vector<int>> partnersOf(numAtoms);
    for (const std::pair<int, int>& p : pairs) {
        partnersOf[p.first].push_back(p.second);
        partnersOf[p.second].push_back(p.first);
    }
    std::vector<int> first(1, 0), list;
    for (const std::vector<int>& p : partnersOf) {
        list.insert(list.end(), p.begin(), p.end());
        first.push_back((int) list.size());
    }
    uploadInts(cc, start, first, name + "Start");
    uploadInts(cc, partners, list, name);
}

void DPDPlugin::uploadMixed4(ComputeContext& cc, ComputeArray& array, const std::vector<double>& rows, const std::string& name) {
    const size_t n = std::max((size_t) 1, rows.size() / 4);
    if (mixedIsDouble(cc)) {
        std::vector<mm_double4> data(n, mm_double4(0, 0, 0, 0));
        for (size_t k = 0; 4 * k < rows.size(); k++)
            data[k] = mm_double4(rows[4 * k], rows[4 * k + 1], rows[4 * k + 2], rows[4 * k + 3]);
        uploadResized(cc, array, data, name);
    }
    else {
        std::vector<mm_float4> data(n, mm_float4(0, 0, 0, 0));
        for (size_t k = 0; 4 * k < rows.size(); k++)
            data[k] = mm_float4((float) rows[4 * k], (float) rows[4 * k + 1], (float) rows[4 * k + 2], (float) rows[4 * k + 3]);
        uploadResized(cc, array, data, name);
    }
}

CommonCellScan::CommonCellScan(ComputeContext& cc, ComputeProgram program) : cc(cc) {
    // Every argument is set at each call (the arrays are resized with the box).
    blockKernel = createKernelWithArgs(program, "scanCellBlocks", 4);
    sumsKernel = createKernelWithArgs(program, "scanBlockSums", 4);
    addKernel = createKernelWithArgs(program, "addBlockStarts", 3);
}

void CommonCellScan::execute(int numCells, ComputeArray& cellCount, ComputeArray& cellStart) {
    const int numBlocks = (numCells + BlockSize - 1) / BlockSize;
    if (!blockSums.isInitialized())
        blockSums.initialize<int>(cc, numBlocks, "dpdCellBlockSums");
    else if ((int) blockSums.getSize() < numBlocks)
        blockSums.resize(numBlocks);
    blockKernel->setArg(0, numCells);
    blockKernel->setArg(1, cellCount);
    blockKernel->setArg(2, cellStart);
    blockKernel->setArg(3, blockSums);
    blockKernel->execute(numBlocks * BlockSize, BlockSize);
    sumsKernel->setArg(0, numBlocks);
    sumsKernel->setArg(1, numCells);
    sumsKernel->setArg(2, blockSums);
    sumsKernel->setArg(3, cellStart);
    sumsKernel->execute(BlockSize, BlockSize);
    addKernel->setArg(0, numCells);
    addKernel->setArg(1, blockSums);
    addKernel->setArg(2, cellStart);
    addKernel->execute(numCells);
}

DeviceBox::DeviceBox(const Vec3* box) {
    inverseBoxRows(box, rows);
    for (int d = 0; d < 3; d++) {
        size[d] = box[d][d];
        inverse[d] = 1 / box[d][d];
        c[d] = box[2][d];
        rowX[d] = rows[0][d];
    }
    size[3] = box[1][0];
    rowYZ[0] = rows[1][1];
    rowYZ[1] = rows[1][2];
    rowYZ[2] = rows[2][2];
}

DeviceBox DeviceBox::open(const Vec3& lo, const Vec3& extent) {
    DeviceBox box;
    for (int d = 0; d < 3; d++) {
        box.rows[d][d] = 1 / extent[d];
        box.origin[d] = lo[d];
    }
    box.rowX[0] = box.rows[0][0];
    box.rowYZ[0] = box.rows[1][1];
    box.rowYZ[2] = box.rows[2][2];
    return box;
}

int DeviceBox::cellsAcross(int k, double width) const {
    const double cells = std::floor(1 / (width * std::sqrt(rows[k].dot(rows[k]))));
    return (int) std::max(1.0, std::min(cells, (double) MaxCellsAcross));
}

constexpr int CommonGridBox::Slots;

CommonGridBox::CommonGridBox(ComputeContext& cc, ComputeProgram program, const std::string& owner, bool periodic, bool movingOnly) :
        cc(cc), owner(owner), periodic(periodic), movingOnly(movingOnly) {
    if (periodic)
        return;
    bounds.initialize(cc, 6 * Slots, mixedIsDouble(cc) ? sizeof(double) : sizeof(float), "dpdParticleBounds");
    kernel = program->createKernel("findBounds");
    kernel->addArg(cc.getNumAtoms());
    kernel->addArg(cc.getPosq());
    kernel->addArg(cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq());
    kernel->addArg(cc.getVelm());
    kernel->addArg(movingOnly ? 1 : 0);
    kernel->addArg(Slots);
    kernel->addArg(bounds);
}

DeviceBox CommonGridBox::current(double cutoff, const std::string& what) {
    if (!periodic)
        return openGrid(cutoff);
    Vec3 vectors[3];
    cc.getPeriodicBoxVectors(vectors[0], vectors[1], vectors[2]);
    requireCutoffFitsBox(owner, what, cutoff, vectors);
    return DeviceBox(vectors);
}

DeviceBox CommonGridBox::openGrid(double cutoff) {
    kernel->execute(Slots);
    const std::vector<double> values = downloadMixed(cc, bounds);
    Vec3 lo(1e30, 1e30, 1e30), hi(-1e30, -1e30, -1e30);
    for (int t = 0; t < Slots; t++)
        for (int d = 0; d < 3; d++) {
            lo[d] = std::min(lo[d], values[6 * t + d]);
            hi[d] = std::max(hi[d], values[6 * t + 3 + d]);
        }
    Vec3 extent;
    for (int d = 0; d < 3; d++) {
        if (lo[d] > hi[d])  // nothing moves: any grid will do
            lo[d] = hi[d] = 0;
        extent[d] = std::max(hi[d] - lo[d], cutoff) * (1 + 1e-12);
    }
    return DeviceBox::open(lo, extent);
}

CommonCellList::CommonCellList(ComputeContext& cc, ComputeProgram program, const std::string& owner, bool periodic,
                               bool boundsOfMoving) :
        cc(cc), owner(owner), scan(cc, program), grid(cc, program, owner, periodic, boundsOfMoving) {
    const int n = std::max(cc.getNumAtoms(), 1);
    atomCell.initialize<int>(cc, n, "dpdAtomCell");
    cellAtoms.initialize<int>(cc, n, "dpdCellAtoms");
    // Every argument is set at each build (the arrays are resized with the box).
    clearKernel = createKernelWithArgs(program, "clearCells", 2);
    assignKernel = createKernelWithArgs(program, "assignCells", 9);
    fillKernel = createKernelWithArgs(program, "fillCells", 5);
}

void CommonCellList::build(double cutoff) {
    box = grid.current(cutoff, "the cutoff");
    // A little wider than the cutoff: a position rounded into the next cell still finds its partners.
    for (int d = 0; d < 3; d++)
        numCells[d] = box.cellsAcross(d, cutoff * (1 + 1e-5));
    // The grid grows with the box, an open System's with its bounding box: one particle far
    // out would make millions of empty cells.  Wider cells serve as well; keep a few per particle.
    const long long limit = 8LL * std::max(cc.getNumAtoms(), 8);
    while ((long long) numCells[0] * numCells[1] * numCells[2] > limit) {
        int& widest = *std::max_element(numCells, numCells + 3);
        widest = (widest + 1) / 2;
    }
    const int total = numCells[0] * numCells[1] * numCells[2];
    if (total != totalCells) {
        totalCells = total;
        if (!cellCount.isInitialized()) {
            cellCount.initialize<int>(cc, total, "dpdCellCount");
            cellStart.initialize<int>(cc, total + 1, "dpdCellStart");
        }
        else {
            cellCount.resize(total);
            cellStart.resize(total + 1);
        }
    }
    const int n = cc.getNumAtoms();
    clearKernel->setArg(0, total);
    clearKernel->setArg(1, cellCount);
    clearKernel->execute(total);
    assignKernel->setArg(0, n);
    assignKernel->setArg(1, cc.getPosq());
    assignKernel->setArg(2, cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq());
    setMixed4Arg(cc, assignKernel, 3, box.origin);
    setMixed4Arg(cc, assignKernel, 4, box.rowX);
    setMixed4Arg(cc, assignKernel, 5, box.rowYZ);
    assignKernel->setArg(6, mm_int4(numCells[0], numCells[1], numCells[2], grid.isPeriodic() ? 1 : 0));
    assignKernel->setArg(7, atomCell);
    assignKernel->setArg(8, cellCount);
    assignKernel->execute(n);
    scan.execute(total, cellCount, cellStart);
    fillKernel->setArg(0, n);
    fillKernel->setArg(1, atomCell);
    fillKernel->setArg(2, cellStart);
    fillKernel->setArg(3, cellCount);
    fillKernel->setArg(4, cellAtoms);
    fillKernel->execute(n);
}

void CommonCellList::setArgs(ComputeKernel& kernel, int first) {
    setMixed4Arg(cc, kernel, first, box.size);
    setMixed4Arg(cc, kernel, first + 1, box.inverse);
    setMixed4Arg(cc, kernel, first + 2, box.c);
    kernel->setArg(first + 3, mm_int4(numCells[0], numCells[1], numCells[2], grid.isPeriodic() ? 1 : 0));
    kernel->setArg(first + 4, atomCell);
    kernel->setArg(first + 5, cellStart);
    kernel->setArg(first + 6, cellAtoms);
}
