"""OpenEXR files for the end-to-end tests (displacement, depth and weight
maps), with the standard library only; the PNG counterpart is pngwrite.py.

exr(path, w, h, chans): writes a w x h scanline file of 32-bit float
channels without compression; chans maps each channel's name to f(x, y).
Import with PYTHONPATH set to this folder (python3 -B: no bytecode cache in
the source tree).
"""
import struct


def exr(path, w, h, chans):
    """chans: {name: f(x, y) -> float}; scanline, 32-bit float, no compression"""
    names = sorted(chans)  # OpenEXR lists channels in name order
    def attr(n, t, v): return n.encode() + b'\0' + t.encode() + b'\0' + struct.pack('<i', len(v)) + v
    chlist = b''.join(n.encode() + b'\0' + struct.pack('<iB3xii', 2, 0, 1, 1) for n in names) + b'\0'
    box = struct.pack('<4i', 0, 0, w - 1, h - 1)
    hdr = (b'\x76\x2f\x31\x01' + struct.pack('<i', 2) + attr('channels', 'chlist', chlist)
           + attr('compression', 'compression', b'\0') + attr('dataWindow', 'box2i', box)
           + attr('displayWindow', 'box2i', box) + attr('lineOrder', 'lineOrder', b'\0')
           + attr('pixelAspectRatio', 'float', struct.pack('<f', 1))
           + attr('screenWindowCenter', 'v2f', struct.pack('<2f', 0, 0))
           + attr('screenWindowWidth', 'float', struct.pack('<f', 1)) + b'\0')
    lines = []
    for y in range(h):
        data = b''.join(struct.pack('<%df' % w, *[chans[n](x, y) for x in range(w)]) for n in names)
        lines.append(struct.pack('<ii', y, len(data)) + data)
    table, at = bytearray(), len(hdr) + 8 * h
    for line in lines:
        table += struct.pack('<Q', at)
        at += len(line)
    open(path, 'wb').write(hdr + bytes(table) + b''.join(lines))
