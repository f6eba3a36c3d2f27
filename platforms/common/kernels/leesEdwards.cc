/*
 * The sliding boundaries of Lees-Edwards shear after a drift, as LeesEdwardsBoundary does on
 * the host (docs/theory/lees-edwards.md): every molecule whose centre has left 0 <= y < Ly is
 * brought back by whole b = (tilt, Ly, 0), the box's new b, and the x velocities of its
 * particles that move (1/m != 0) are lowered by as many U: in velm (by slot) and, with
 * jumpAlso, in alsoJump (by atom; velocities a step carries beside them).  Molecules are
 * listed by atom index (moleculeStart, moleculeAtoms); slotOf[atom] = its slot.
 */

KERNEL void findSlots(int numAtoms, GLOBAL const int* RESTRICT atomIndex, GLOBAL int* RESTRICT slotOf) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE)
        slotOf[atomIndex[k]] = k;
}

KERNEL void slideMolecules(int numMolecules, GLOBAL const int* RESTRICT moleculeStart, GLOBAL const int* RESTRICT moleculeAtoms,
        GLOBAL const int* RESTRICT slotOf, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL mixed4* RESTRICT velm, GLOBAL mixed4* RESTRICT alsoJump, int jumpAlso, mixed4 boxSize, mixed invHeight,
        mixed U) {
    for (int m = GLOBAL_ID; m < numMolecules; m += GLOBAL_SIZE) {
        const int first = moleculeStart[m], last = moleculeStart[m+1];
        mixed y = 0;
        for (int t = first; t < last; t++)
            y += loadPosition(posq, posqCorrection, slotOf[moleculeAtoms[t]]).y;
        const mixed crossings = floor(y/(last-first)*invHeight);
        if (crossings == 0)
            continue;
        for (int t = first; t < last; t++) {
            const int a = moleculeAtoms[t], k = slotOf[a];
            mixed4 r = loadPosition(posq, posqCorrection, k);
            r.x -= crossings*boxSize.w;
            r.y -= crossings*boxSize.y;
            storePosition(posq, posqCorrection, k, r);
            mixed4 v = velm[k];
            if (v.w == 0)
                continue;
            v.x -= crossings*U;
            velm[k] = v;
            if (jumpAlso)
                alsoJump[a].x -= crossings*U;
        }
    }
}
