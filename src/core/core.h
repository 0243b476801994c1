/* Internal helpers of the core layer, shared by every layer of the library. */
#ifndef JND_CORE_H
#define JND_CORE_H

#include <stddef.h>
#include <stdint.h>
#include "jnd.h"

/* Records a one-line message for jnd_last_error() and returns status. */
jnd_status jnd_fail(jnd_status status, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Checked allocation: NULL (and an error recorded) on failure or overflow. */
void *jnd_alloc(size_t count, size_t size);
void *jnd_calloc(size_t count, size_t size);

/* A shared library opened when a program first calls into it (dlopen),
 * for the dependencies only some commands use: `jnd diff` maps, relocates
 * and initialises none of assimp's or LAPACK's ten libraries (about 2.5 ms
 * of its start-up). jnd_lazy_symbol gives the address of `name` in it, or
 * NULL with a message naming the library (jnd_last_error) when either
 * cannot be had. Any thread may call it; a library is opened once. */
typedef struct {
  const char *soname; /* as the linker records it, e.g. "libassimp.so.5" */
  void *_Atomic handle;
} jnd_lazy_lib;
void *jnd_lazy_symbol(jnd_lazy_lib *lib, const char *name);
/* In a shim's body: f, the function `name` of lib, of pointer type `type`,
 * looked up once (NULL, with the loader's message, where it cannot be had). */
#define JND_LAZY_FN(lib, type, name)            \
  static _Atomic(type) name##_p;                \
  __typeof__(type) f = name##_p;                \
  if (!f) name##_p = f = (__typeof__(type))jnd_lazy_symbol(lib, #name)

/* Checks w × h × c against the stated limits. */
jnd_status jnd_check_size(int w, int h, int c, const char *what);

/* The index of the first of v[0..n) that is not in [lo, hi] (NaN never
 * is), or n when all are: a branch-free pass over blocks, so that checking
 * a whole image costs about as much as reading it. */
size_t jnd_first_outside(const float *v, size_t n, float lo, float hi);

/* Number of threads to use for a request (0 = OpenMP default). */
int jnd_threads(int requested);
/* Runs OpenMP regions without their own thread count on n threads (n > 0)
 * until jnd_threads_leave(returned value); n = 0 changes nothing. For code
 * that must not spin workers against another pool of threads (a CPU
 * rasteriser's). */
int jnd_threads_enter(int n);
void jnd_threads_leave(int previous);

/* A deterministic generator (SplitMix64 seeding xoshiro256**): the same
 * seed gives the same sequence on every machine. */
typedef struct { uint64_t s[4]; } jnd_rng;
void jnd_rng_seed(jnd_rng *r, uint64_t seed);
uint64_t jnd_rng_next(jnd_rng *r);
double jnd_rng_uniform(jnd_rng *r);   /* [0, 1) */
double jnd_rng_normal(jnd_rng *r);    /* standard normal (Box–Muller) */

/* Marks a function whose loops carry the model's arithmetic: it is compiled
 * for AVX-512 (x86-64-v4) and AVX2 (x86-64-v3) as well as for baseline
 * x86-64, and the loader picks the version the CPU runs (GCC function
 * multiversioning). Contraction to FMA is off (CMakeLists.txt) and the
 * loops are element-wise (no reduction whose order depends on the vector's
 * width), so every version computes the same bits. JND_HOT_AVX2 leaves out
 * the AVX-512 version, for loops of table look-ups: GCC vectorises those
 * for AVX-512 with byte extracts and inserts in place of loads, twice as
 * slow as its AVX2 version (png_rgb_to_planes; docs/speed.md, "Ninth
 * pass"). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && !defined(JND_NO_CLONES)
#define JND_HOT __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#define JND_HOT_AVX2 __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define JND_HOT
#define JND_HOT_AVX2
#endif

/* The 64-bit finaliser of MurmurHash3 (fmix64): every input bit moves every
 * output bit. The procedural textures' noise and the judge's state
 * digests mix with it. */
static inline uint64_t jnd_mix64(uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return x;
}

static inline double jnd_clampd(double v, double lo, double hi) {
  return v < lo ? lo : v > hi ? hi : v;
}
static inline int jnd_clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

#endif
