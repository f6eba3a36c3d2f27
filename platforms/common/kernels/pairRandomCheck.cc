/* For the tests: the device's pair words and normal numbers for a list of keys (stream, step low, step high, i, j). */
KERNEL void drawPairRandom(int numKeys, unsigned int seed, GLOBAL const int* RESTRICT keys, GLOBAL unsigned int* RESTRICT words,
        GLOBAL float* RESTRICT normals) {
    for (int n = GLOBAL_ID; n < numKeys; n += GLOBAL_SIZE) {
        GLOBAL const int* key = keys+5*n;
        const PhiloxWords w = pairWords(seed, (unsigned int) key[0], (unsigned int) key[1], (unsigned int) key[2], key[3], key[4]);
        for (int m = 0; m < 4; m++)
            words[4*n+m] = w.v[m];
        normals[n] = (float) boxMuller(w);
    }
}
