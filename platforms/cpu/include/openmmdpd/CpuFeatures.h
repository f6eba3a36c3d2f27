#ifndef OPENMMDPD_CPUFEATURES_H_
#define OPENMMDPD_CPUFEATURES_H_

/*
 * The x86 vector units the CPU platform's hand-vectorised code is built for (target
 * attributes) and called on only where the processor has them; each checked once.
 */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define OPENMMDPD_X86_VECTORS

namespace DPDPlugin {

inline bool haveAVX2() {
    static const bool have = __builtin_cpu_supports("avx2");
    return have;
}

inline bool haveAVX512() {
    static const bool have = __builtin_cpu_supports("avx512f");
    return have;
}

/**
 * Four doubles as one AVX2 register, with C's arithmetic lane by lane: what the AVX2 code
 * computes with.  Passed or returned by value, it crosses a call between code built for
 * different vector units differently on each side (-Wpsabi), so its users keep it in
 * inlined functions.
 */
typedef double Lane4 __attribute__((vector_size(4 * sizeof(double))));

} // namespace DPDPlugin

#endif

#endif
