"""PNG files for the end-to-end tests, with the standard library only.

png(path, w, h, ch, f, bits=8): writes a w x h image of ch channels (1 grey,
3 RGB, 4 RGBA), 8 or 16 bits a sample; f(x, y) gives the ch values of pixel
(x, y) in 0..1. Import with PYTHONPATH set to this folder.
"""
import struct
import zlib


def png(path, w, h, ch, f, bits=8):
    top = (1 << bits) - 1
    fmt = '>' + ('B' if bits == 8 else 'H') * ch
    raw = bytearray()
    for y in range(h):
        raw.append(0)  # filter: none
        for x in range(w):
            raw.extend(struct.pack(fmt, *(max(0, min(top, int(round(v * top)))) for v in f(x, y))))

    def chunk(t, b):
        return struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b) & 0xffffffff)

    colour = {1: 0, 3: 2, 4: 6}[ch]
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, bits, colour, 0, 0, 0))
                           + chunk(b'IDAT', zlib.compress(bytes(raw))) + chunk(b'IEND', b''))
