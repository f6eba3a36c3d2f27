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

} // namespace DPDPlugin

#endif

#endif
