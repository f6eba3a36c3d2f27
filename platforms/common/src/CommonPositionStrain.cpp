#include "openmmdpd/CommonPositionStrain.h"
#include "openmmdpd/CommonCellList.h"
#include "openmm/common/ContextSelector.h"

using namespace DPDPlugin;
using namespace OpenMM;

CommonPositionStrain::CommonPositionStrain(ComputeContext& cc, ComputeProgram program) : cc(cc) {
    ContextSelector selector(cc);
    const int n = cc.getNumAtoms();
    ArrayInterface& posq = cc.getPosq();
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    savedPosq.initialize(cc, std::max(n, 1), posq.getElementSize(), "dpdSavedPosq");
    savedCorrection.initialize(cc, std::max(n, 1), posq.getElementSize(), "dpdSavedPosqCorrection");
    saveKernel = program->createKernel("savePositions");
    saveKernel->addArg(n);
    addArrayArgs(saveKernel, {&posq, &posqCorrection, &cc.getAtomIndexArray(), &savedPosq, &savedCorrection});
    strainKernel = program->createKernel("strainPositions");
    strainKernel->addArg(n);
    addArrayArgs(strainKernel, {&posq, &posqCorrection, &cc.getAtomIndexArray(), &savedPosq, &savedCorrection});
    for (int k = 0; k < 3; k++)
        strainKernel->addArg();  // the axis, the one it moves along, the strain: set per call
    restoreKernel = program->createKernel("restorePositions");
    restoreKernel->addArg(n);
    addArrayArgs(restoreKernel, {&posq, &posqCorrection, &cc.getAtomIndexArray(), &savedPosq, &savedCorrection});
}

void CommonPositionStrain::strain(ContextImpl& context, int a, int b, double strain) {
    ContextSelector selector(cc);
    if (!saved) {
        saveKernel->execute(cc.getNumAtoms());
        saved = true;
    }
    strainKernel->setArg(6, a);
    strainKernel->setArg(7, b);
    setMixedArg(cc, strainKernel, 8, strain);
    strainKernel->execute(cc.getNumAtoms());
}

void CommonPositionStrain::restore(ContextImpl& context) {
    if (!saved)
        return;
    ContextSelector selector(cc);
    restoreKernel->execute(cc.getNumAtoms());
    // Nothing of the sample is left queued when it returns: an OpenCL runtime on the CPU (POCL)
    // builds a kernel at its first launch, and a program that exits during the build crashes.
    ComputeEvent restored = cc.createEvent();
    restored->enqueue();
    restored->wait();
    saved = false;
}

void CommonPositionStrain::setBox(ContextImpl& context, const Vec3* box) {
    ContextSelector selector(cc);
    cc.setPeriodicBoxVectors(box[0], box[1], box[2]);
}
