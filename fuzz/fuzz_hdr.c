/* libFuzzer target: the Radiance HDR (stb_image) decoder on arbitrary bytes. */
#include "fuzz.h"

JND_FUZZ_DECODER(jnd_decode_hdr, "fuzz.hdr")
