/* libFuzzer target: the PNG (chunk validation, then stb_image) decoder on arbitrary bytes. */
#include "fuzz.h"

JND_FUZZ_DECODER(jnd_decode_png, "fuzz.png")
