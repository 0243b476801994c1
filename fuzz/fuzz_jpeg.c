/* libFuzzer target: the JPEG (stb_image) decoder on arbitrary bytes. */
#include "fuzz.h"

JND_FUZZ_DECODER(jnd_decode_jpeg, "fuzz.jpeg")
