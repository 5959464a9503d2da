#!/usr/bin/env python3
"""The Markdown table of bench_memory.sh: peak RSS / CPU / wall per command (rows) and recording
length (columns), from the TSV the script measured.

Usage: bench_memory_table.py MEMORY.tsv OUT.md
       bench_memory_table.py --doc DOC.md OUT.md   (puts OUT.md between DOC.md's table markers)
"""
import sys, collections, datetime, os, platform
BEGIN = "<!-- memory table: written by scripts/dev/bench_memory.sh -->"
END = "<!-- end of memory table -->"
if sys.argv[1] == "--doc":
    doc, table = sys.argv[2], open(sys.argv[3]).read()
    text = open(doc).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"bench_memory_table.py: {doc} has no '{BEGIN}' ... '{END}' markers")
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    open(doc, "w").write(head + BEGIN + "\n" + table + END + tail)
    sys.exit(0)
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])][1:]
lengths = list(dict.fromkeys(r[0] for r in rows))
skipped = [r for r in rows if "(skipped" in r[2]]
rows = [r for r in rows if "(skipped" not in r[2]]
whats = list(dict.fromkeys(r[2] for r in rows))
cell = {(r[0], r[2]): (r[3], r[4], r[5]) for r in rows}
samples = {r[0]: r[1] for r in rows if r[1] != "-"}
def hdr(l):
    m = int(l)
    return (f"{m // 60} h" if m % 60 == 0 and m >= 120 else f"{m} min") + (f" ({int(samples[l]):,} samples)" if l in samples else "")
with open(sys.argv[2], "w") as f:
    f.write(f"Measured {datetime.date.today().isoformat()} on {os.cpu_count()} cores "
            f"({platform.machine()}), load average {os.getloadavg()[0]:.1f} at the end of the run.\n\n")
    f.write("| peak RSS MB / CPU s / wall s | " + " | ".join(hdr(l) for l in lengths) + " |\n")
    f.write("|---|" + "---|" * len(lengths) + "\n")
    for w in whats:
        cells = []
        for l in lengths:
            v = cell.get((l, w))
            cells.append("-" if v is None or v[0] == "-" else f"**{v[0]}** / {v[1]} / {v[2]}")
        f.write(f"| `{w}` | " + " | ".join(cells) + " |\n")
    for r in skipped:
        f.write(f"\nNot measured: {hdr(r[0])}, {r[2].replace(' (skipped, ', ', ')[:-1]}.\n")
print(open(sys.argv[2]).read())
