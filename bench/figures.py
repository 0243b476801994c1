"""The memory figures bench/*.sh print, read from a command's JSON report in
one place (issue 25): texres's and pca's result.memory (each unique image
once, with its mip chain, whatever number of slots or materials sample it),
in MiB (2^20 bytes). tests/e2e/report_memory.sh runs this on a model whose
materials share an image and checks the printed MiB against the unique
images' bytes, so that a bench line that counted a shared image once per
slot fails a test.

  python3 bench/figures.py memory REPORT.json   one line: texres or pca's memory
"""
import json
import sys

MIB = 2.0 ** 20


def mib(nbytes):
    """bytes as the MiB text every bench line uses"""
    return "%.3f MiB" % (nbytes / MIB)


def memory_line(report):
    """the memory line of a texres or pca report (the parsed JSON)"""
    mem = report["result"]["memory"]
    images = mem["images"]
    before, after = mem["before_bytes"], mem["after_bytes"]
    change = 100.0 * (after / before - 1) if before else 0.0
    line = "memory (%d unique images, RGBA8 + mips): %s -> %s (%+.0f%%)" % (len(images), mib(before), mib(after), change)
    if report["command"] == "texres":
        line += "; block-compressed %s -> %s" % (mib(mem["block_before_bytes"]), mib(mem["block_after_bytes"]))
    elif report["command"] == "pca":
        line += " as %d packed textures" % len(mem["textures"])
    return line


def main(argv):
    if len(argv) != 3 or argv[1] != "memory":
        sys.stderr.write(__doc__)
        return 2
    with open(argv[2]) as f:
        print(memory_line(json.load(f)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
