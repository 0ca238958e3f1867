// IILFM_AVX2_CLONES: compile a hot loop's function twice, for AVX2 and for the x86-64 baseline,
// and let the loader pick one. AVX2 alone, without FMA, so no multiply-add is fused and both
// versions round alike. Empty where clones cannot work: ThreadSanitizer (the clones' load-time
// resolver runs before its runtime and crashes) and compilers or targets without the attribute.
#pragma once

#if defined(__SANITIZE_THREAD__)
#define IILFM_NO_CLONES
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define IILFM_NO_CLONES
#endif
#endif

#if !defined(IILFM_NO_CLONES) && defined(__GNUC__) && defined(__x86_64__)
#define IILFM_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
// For bit counting: the x86-64 baseline has no POPCNT instruction, and GCC calls libgcc for
// every count there.
#define IILFM_POPCNT_CLONES __attribute__((target_clones("popcnt", "default")))
#else
#define IILFM_AVX2_CLONES
#define IILFM_POPCNT_CLONES
#endif
