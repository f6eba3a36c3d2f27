/*
 * Extended DPD's pair variables on the device (ReferencePairMemory is the definition,
 * docs/theory/edpd.md).  The memory is a table by atom: row a holds the pairs (a, b), b > a,
 * sorted by b, `capacity` entries apart, count[a] of them.  An entry is in range (s and w^2
 * at the table's step), archived (s at archivedStep, the step of its last update), or both:
 * a pair that came back keeps its old archived entry until it is forgotten, as the
 * Reference's memory counts it.  A step merges the old table with the pairs in range now
 * into a new one, each row by one work item, so no entry is shared and no order matters.
 *
 * Random numbers as PairRandom keys them: AuxiliaryRecall (4) at step n for a pair drawn or
 * caught up to step n, AuxiliaryNoise (3) at step n + 1 for the step from n to n + 1.
 */

#define EDPD_IN_RANGE 1
#define EDPD_ARCHIVED 2
#ifdef __OPENCL_VERSION__
#define EDPD_ATOMIC_MAX(destination, value) atomic_max(destination, value)
#else
#define EDPD_ATOMIC_MAX(destination, value) atomicMax(destination, value)
#endif

/* A step of the memory: the recurrence, and what the merge kernel was told (see edpdMergePairs). */
typedef struct {
    mixed rho, invD, noisePerLambda, variancePerLambda, alpha;
    unsigned int seed;
    mm_long n, inRangeStep, forgetSteps;
    int advance, forgetNow;
} EdpdStep;

/* An entry of the table: its state (EDPD_IN_RANGE, EDPD_ARCHIVED), s and w^2 in range, s archived and its step. */
typedef struct {
    int flags;
    mixed value, weight2, archived;
    mm_long archivedStep;
} EdpdEntry;

/* lambda = alpha gamma_ab f_ab of the pair, gamma_ab = 2 mu_ab friction. */
inline DEVICE mixed edpdLambda(int a, int b, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomType, int numTypes,
        GLOBAL const mixed4* RESTRICT typeParams, GLOBAL const int* RESTRICT exceptionStart, GLOBAL const int* RESTRICT exceptionPartner,
        GLOBAL const mixed* RESTRICT exceptionFactor, mixed alpha) {
    const mixed friction = typeParams[atomType[a]*numTypes+atomType[b]].x;
    const mixed factor = thermostatFactor(a, b, exceptionStart, exceptionPartner, exceptionFactor);
    return alpha*(2*friction/(velocity[a].w+velocity[b].w))*factor;
}

/*
 * s at step n of a pair last known as s at step `last` (known), or never seen: caught up with
 * h constant, or drawn anew once forgotten (ReferencePairMemory::catchUp).
 */
inline DEVICE mixed edpdRecall(int known, mixed s, mm_long last, mixed lambda, EdpdStep st, int a, int b) {
    if (known && last == st.n)
        return s;
    const mm_long gap = st.n-last;
    const bool forgotten = (!known || gap < 0 || gap >= st.forgetSteps);
    const mixed xi = boxMuller(pairWords(st.seed, 4, (unsigned int) st.n, (unsigned int) (st.n>>32), a, b));
    return edpdCaughtUp(forgotten ? 0 : s, forgotten ? 0 : pow(st.rho, (mixed) gap), lambda*st.variancePerLambda, xi);
}

/* s at step n + 1 from s at n and the pair's w^2 at n and n + 1 (0 out of range). */
inline DEVICE mixed edpdNext(mixed s, mixed w2Old, mixed w2New, mixed cutoff, mixed lambda, EdpdStep st, int a, int b) {
    const mm_long next = st.n+1;
    const mixed w = boxMuller(pairWords(st.seed, 3, (unsigned int) next, (unsigned int) (next>>32), a, b));
    return edpdNextValue(s, st.rho, st.invD, lambda, edpdPotentialChange(cutoff, w2Old, w2New), st.noisePerLambda, w);
}

/*
 * The entry of the pair (a, b) after the step, from its old one (flags 0 if none), and whether
 * it is in range now, with w2New: as ReferencePairMemory::bind (advance = 0) and advance.
 */
inline DEVICE EdpdEntry edpdStepEntry(EdpdEntry old, int inRangeNow, mixed w2New, mixed cutoff, mixed lambda, EdpdStep st, int a, int b) {
    EdpdEntry e = old;
    e.flags = old.flags & EDPD_ARCHIVED;
    const int wasInRange = old.flags & EDPD_IN_RANGE;
    if (inRangeNow) {
        // Its s at n (kept, caught up or drawn), then one step if advancing.
        const mixed s = (wasInRange ? edpdRecall(1, old.value, st.inRangeStep, lambda, st, a, b) :
                         edpdRecall(old.flags & EDPD_ARCHIVED, old.archived, old.archivedStep, lambda, st, a, b));
        e.value = (st.advance ? edpdNext(s, wasInRange ? old.weight2 : 0, w2New, cutoff, lambda, st, a, b) : s);
        e.weight2 = w2New;
        e.flags |= EDPD_IN_RANGE;
    }
    else if (wasInRange) {
        // Left its cutoff: archived, after one last step to w = 0 if advancing.
        e.archived = (st.advance ? edpdNext(old.value, old.weight2, 0, cutoff, lambda, st, a, b) : old.value);
        e.archivedStep = (st.advance ? st.n+1 : st.inRangeStep);
        e.flags |= EDPD_ARCHIVED;
    }
    if (st.forgetNow && (e.flags & EDPD_ARCHIVED) && st.n+1-e.archivedStep >= st.forgetSteps)
        e.flags &= ~EDPD_ARCHIVED;
    return e;
}

/*
 * The pairs (a, b > a) within their cutoff now, among the particles that move: sorted by b
 * into row a of candidates, with their w^2.  Returns how many (written while they fit).
 */
inline DEVICE int edpdPairsInRange(int k, int a, mixed4 ra, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomType, int numTypes,
        GLOBAL const mixed4* RESTRICT typeParams, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells,
        GLOBAL const int* RESTRICT atomCell, GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms, int capacity,
        GLOBAL int* RESTRICT candidatePartner, GLOBAL mixed* RESTRICT candidateWeight2) {
    const int row = a*capacity;
    int count = 0;
    FOR_EACH_NEIGHBOUR_SLOT(s, atomCell[k], numCells, cellStart) {
        const int k2 = cellAtoms[s];
        const int b = atomIndex[k2];
        if (b <= a || velocity[b].w == 0)
            continue;
        const mixed4 d = nearestDisplacement(ra, loadPosition(posq, posqCorrection, k2), boxSize, invBoxSize, boxC);
        const mixed4 p = typeParams[atomType[a]*numTypes+atomType[b]];  // friction, rc, s, rc^2
        const mixed r2 = d.x*d.x+d.y*d.y+d.z*d.z;
        if (r2 >= p.w || r2 == 0)
            continue;
        const mixed w = pairLinearWeight(sqrt(r2), p.y);
        if (count < capacity) {  // insertion by partner
            int at = count;
            for (; at > 0 && candidatePartner[row+at-1] > b; at--) {
                candidatePartner[row+at] = candidatePartner[row+at-1];
                candidateWeight2[row+at] = candidateWeight2[row+at-1];
            }
            candidatePartner[row+at] = b;
            candidateWeight2[row+at] = w*w;
        }
        count++;
    }
    return count;
}

/*
 * One step of the memory (advance != 0: from step n to n + 1, the pairs in range found at the
 * positions of n + 1) or a (re)start at step n (advance = 0: the pairs in range at n, each
 * with its s kept, caught up or drawn, as ReferencePairMemory::bind; inRangeStep the old
 * table's step).  forgetNow: drop the archived entries away forgetSteps or more at n + 1.
 * needed[0] becomes the largest row (or candidate list) that did not fit `capacity`.
 */
KERNEL void edpdMergePairs(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomType, int numTypes,
        GLOBAL const mixed4* RESTRICT typeParams, GLOBAL const int* RESTRICT exceptionStart, GLOBAL const int* RESTRICT exceptionPartner,
        GLOBAL const mixed* RESTRICT exceptionFactor, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells,
        GLOBAL const int* RESTRICT atomCell, GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms, int capacity,
        GLOBAL const int* RESTRICT oldPartner, GLOBAL const int* RESTRICT oldFlags, GLOBAL const mixed* RESTRICT oldValue,
        GLOBAL const mixed* RESTRICT oldWeight2, GLOBAL const mixed* RESTRICT oldArchived, GLOBAL const mm_long* RESTRICT oldArchivedStep,
        GLOBAL const int* RESTRICT oldCount, GLOBAL int* RESTRICT newPartner, GLOBAL int* RESTRICT newFlags, GLOBAL mixed* RESTRICT newValue,
        GLOBAL mixed* RESTRICT newWeight2, GLOBAL mixed* RESTRICT newArchived, GLOBAL mm_long* RESTRICT newArchivedStep,
        GLOBAL int* RESTRICT newCount, GLOBAL int* RESTRICT candidatePartner, GLOBAL mixed* RESTRICT candidateWeight2,
        unsigned int seed, mm_long n, mm_long inRangeStep, int advance, mm_long forgetSteps, int forgetNow, mixed rho, mixed invD,
        mixed noisePerLambda, mixed variancePerLambda, mixed alpha, GLOBAL int* RESTRICT needed) {
    const EdpdStep st = {rho, invD, noisePerLambda, variancePerLambda, alpha, seed, n, inRangeStep, forgetSteps, advance, forgetNow};
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const int row = a*capacity;
        const int fresh = (velocity[a].w == 0 ? 0 :
                edpdPairsInRange(k, a, loadPosition(posq, posqCorrection, k), posq, posqCorrection, atomIndex, velocity, atomType, numTypes,
                                 typeParams, boxSize, invBoxSize, boxC, numCells, atomCell, cellStart, cellAtoms, capacity, candidatePartner,
                                 candidateWeight2));
        if (fresh > capacity) {
            EDPD_ATOMIC_MAX(needed, fresh);
            continue;
        }
        // Both lists are sorted by partner: one pass over their union.
        const int old = oldCount[a];
        int io = 0, ic = 0, out = 0;
        while (io < old || ic < fresh) {
            const int bOld = (io < old ? oldPartner[row+io] : numAtoms), bNew = (ic < fresh ? candidatePartner[row+ic] : numAtoms);
            const int b = (bOld < bNew ? bOld : bNew);
            EdpdEntry e = {0, 0, 0, 0, 0};
            if (bOld == b) {
                const EdpdEntry stored = {oldFlags[row+io], oldValue[row+io], oldWeight2[row+io], oldArchived[row+io], oldArchivedStep[row+io]};
                e = stored;
                io++;
            }
            const int inRangeNow = (bNew == b);
            // An entry that is only archived just ages: it needs no lambda.
            const mixed lambda = (inRangeNow || (e.flags & EDPD_IN_RANGE) ?
                    edpdLambda(a, b, velocity, atomType, numTypes, typeParams, exceptionStart, exceptionPartner, exceptionFactor, alpha) : 0);
            e = edpdStepEntry(e, inRangeNow, inRangeNow ? candidateWeight2[row+ic] : 0, typeParams[atomType[a]*numTypes+atomType[b]].y,
                              lambda, st, a, b);
            ic += inRangeNow;
            if (e.flags != 0 && out < capacity) {
                newPartner[row+out] = b;
                newFlags[row+out] = e.flags;
                newValue[row+out] = e.value;
                newWeight2[row+out] = e.weight2;
                newArchived[row+out] = e.archived;
                newArchivedStep[row+out] = e.archivedStep;
            }
            out += (e.flags != 0 ? 1 : 0);
        }
        newCount[a] = (out < capacity ? out : capacity);
        if (out > capacity)
            EDPD_ATOMIC_MAX(needed, out);
    }
}

/* The s of the pair (lo, hi) in range, from row lo (binary search); 0 and *found = false if it is not. */
inline DEVICE mixed edpdValueInRange(int lo, int hi, int capacity, GLOBAL const int* RESTRICT partner, GLOBAL const int* RESTRICT flags,
        GLOBAL const mixed* RESTRICT value, GLOBAL const int* RESTRICT count, bool* found) {
    int first = lo*capacity, last = first+count[lo]-1;
    while (first <= last) {
        const int middle = (first+last)/2;
        if (partner[middle] < hi)
            first = middle+1;
        else if (partner[middle] > hi)
            last = middle-1;
        else {
            *found = (flags[middle] & EDPD_IN_RANGE) != 0;
            return *found ? value[middle] : 0;
        }
    }
    *found = false;
    return 0;
}

/*
 * The pair forces of the variables, c e on lo with c = -w s (-grad_lo h_k s_k), gathered per
 * particle as dpdPairForces gathers: out[atom + d numAtoms].  A pair counts where it is in
 * range both here and in the table, a test both of its particles make alike.  With
 * virial != 0, r c e e^T of each pair goes into its lo slot's row.
 */
KERNEL void edpdPairForces(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomType, int numTypes,
        GLOBAL const mixed4* RESTRICT typeParams, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells,
        GLOBAL const int* RESTRICT atomCell, GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms, int capacity,
        GLOBAL const int* RESTRICT partner, GLOBAL const int* RESTRICT flags, GLOBAL const mixed* RESTRICT value,
        GLOBAL const int* RESTRICT count, GLOBAL mm_long* RESTRICT out, int virial, int paddedNumAtoms, GLOBAL mixed* RESTRICT virialRows) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 ra = loadPosition(posq, posqCorrection, k);
        mm_long f[3] = {0, 0, 0};
        mixed w6[6] = {0, 0, 0, 0, 0, 0};
        if (velocity[a].w != 0)
            FOR_EACH_NEIGHBOUR_SLOT(s, atomCell[k], numCells, cellStart) {
                const int k2 = cellAtoms[s];
                const int b = atomIndex[k2];
                if (k2 == k || velocity[b].w == 0)
                    continue;
                const mixed4 rb = loadPosition(posq, posqCorrection, k2);
                const bool aIsLo = (a < b);
                const mixed4 d = loHiDisplacement(aIsLo, ra, rb, boxSize, invBoxSize, boxC);
                const mixed4 p = typeParams[atomType[aIsLo ? a : b]*numTypes+atomType[aIsLo ? b : a]];
                const mixed r2 = d.x*d.x+d.y*d.y+d.z*d.z;
                if (r2 >= p.w || r2 == 0)
                    continue;
                bool found;
                const mixed sk = edpdValueInRange(aIsLo ? a : b, aIsLo ? b : a, capacity, partner, flags, value, count, &found);
                if (!found)
                    continue;
                const mixed r = sqrt(r2);
                const mixed c = -pairLinearWeight(r, p.y)*sk;
                const mm_long sign = (aIsLo ? 1 : -1);
                f[0] += sign*toFixed(d.x/r*c);
                f[1] += sign*toFixed(d.y/r*c);
                f[2] += sign*toFixed(d.z/r*c);
                if (aIsLo && virial)
                    addVirialAlong(w6, d.x, d.y, d.z, c/r);
            }
        for (int d = 0; d < 3; d++)
            out[a+d*numAtoms] = f[d];
        if (virial)
            addVirialRow(virialRows, k, paddedNumAtoms, w6);
    }
}

/* carried[atom] = FC[slot] + the variables' forces[atom]; with kick, v += dt/(2m) carried and the step's velocity check. */
KERNEL void edpdCarryForce(int numAtoms, int paddedNumAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT conservative, GLOBAL const mm_long* RESTRICT auxiliary, GLOBAL mm_long* RESTRICT carried,
        int kick, mixed dt, mixed bound, GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        for (int d = 0; d < 3; d++)
            carried[a+d*numAtoms] = conservative[k+d*paddedNumAtoms]+auxiliary[a+d*numAtoms];
        if (!kick)
            continue;
        const mixed4 v = addScaledForce(velm[k], carried, a, numAtoms, (mixed) 0.5f*dt*velm[k].w);
        velm[k] = v;
        checkVelocity(v, bound, status);
    }
}

/* The Context's step count was set from outside: every archived step moves by `shift`. */
KERNEL void edpdRenumberSteps(int numAtoms, int capacity, GLOBAL const int* RESTRICT count, GLOBAL mm_long* RESTRICT archivedStep,
        mm_long shift) {
    for (int a = GLOBAL_ID; a < numAtoms; a += GLOBAL_SIZE)
        for (int e = 0; e < count[a]; e++)
            archivedStep[a*capacity+e] += shift;
}
