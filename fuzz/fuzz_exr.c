/* libFuzzer target: the OpenEXR (OpenEXRCore) decoder on arbitrary bytes. */
#include "fuzz.h"

JND_FUZZ_DECODER(jnd_decode_exr, "fuzz.exr")
