#!/usr/bin/env python3
"""Where a running Fredholm spends its time inside the machine code lavapipe generated for the stages.

lavapipe (llvmpipe) compiles each stage to x86 code at run time, in anonymous executable mappings that `perf` cannot
name. This script starts a command (normally a long `fredholm render` or `bench`), waits for the stages to be
compiled, samples it with `perf record`, copies the anonymous executable mappings out of the live process with
`gdb` and disassembles them with `objdump`. It prints:
- per mapping and per function in it (split at `push %rbp` prologues): the share of all samples, how many calls
  (texel fetches call a per-binding function) and how many per-lane loops (`cmp $0x8`: a storage-buffer load or store, a
  scratch array entry, an atomic or a subgroup operation is a loop over the 8 lanes of a 256-bit llvmpipe) it holds;
- the hottest instructions, each with the instructions before it (--context).
With --out DIR it keeps the annotated disassembly (DIR/jit_*.asm, each instruction prefixed by its sample share).
tests/bench/RESULTS.md "Speed" ("The wave's arrays as texels, and stores a texel at a time") says what this found.

  python3 tests/bench/profile_jit.py [--wait 5] [--seconds 4] [--top 12] [--out DIR] -- \\
      build/fredholm render scenes/cornell.gltf -o /tmp/p.exr --width 256 --height 256 --spp 512 --quiet

Needs perf (Debian linux-perf), gdb and objdump (binutils), and the right to attach to the child
(/proc/sys/kernel/perf_event_paranoid <= 2 for your own processes; ptrace_scope 0 or 1 with this script as parent).
Standard library only. Figures are shares of the samples taken, not seconds: for timings use `fredholm bench`.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time


def executable_anonymous_mappings(pid):
    mappings = []
    with open(f"/proc/{pid}/maps") as maps:
        for line in maps:
            fields = line.split()
            if len(fields) == 5 and fields[1] == "r-xp":  # no path: code made at run time
                start, end = (int(x, 16) for x in fields[0].split("-"))
                mappings.append((start, end))
    return mappings


def dump_mapping(pid, start, end, path):
    subprocess.run(["gdb", "-p", str(pid), "-batch", "-ex", f"dump memory {path} {start:#x} {end:#x}"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def disassemble(path, start):
    out = subprocess.run(["objdump", "-D", "-b", "binary", "-m", "i386:x86-64", f"--adjust-vma={start:#x}", path],
                         check=True, capture_output=True, text=True).stdout
    instructions = []
    for line in out.splitlines():
        match = re.match(r"\s*([0-9a-f]+):\s+(?:[0-9a-f]{2} )+\s*(.*)", line)
        if match and match.group(2):
            instructions.append((int(match.group(1), 16), match.group(2).strip()))
    return instructions


def sample_shares(perf_data):
    report = subprocess.run(["perf", "report", "-i", perf_data, "--no-children", "--sort", "sym", "--stdio"],
                            check=True, capture_output=True, text=True).stdout
    shares = {}
    for line in report.splitlines():
        match = re.match(r"\s*([0-9.]+)%\s+\[\.\]\s+0x([0-9a-f]+)\s*$", line)
        if match:
            shares[int(match.group(2), 16)] = float(match.group(1))
    return shares


def split_functions(instructions):
    """(first, last) instruction indices of each function: a new one starts at every `push %rbp`."""
    starts = [k for k, (_, text) in enumerate(instructions) if text.startswith("push   %rbp")] or [0]
    if starts[0] != 0:
        starts.insert(0, 0)
    return [(a, b) for a, b in zip(starts, starts[1:] + [len(instructions)])]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--wait", type=float, default=5.0, help="seconds before sampling (the stages compile first)")
    ap.add_argument("--seconds", type=float, default=4.0, help="seconds of sampling")
    ap.add_argument("--top", type=int, default=12, help="hottest instructions to show")
    ap.add_argument("--context", type=int, default=6, help="instructions shown before each hot one")
    ap.add_argument("--out", help="keep the annotated disassembly here")
    ap.add_argument("command", nargs=argparse.REMAINDER, help="-- then the command to profile")
    args = ap.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        raise SystemExit("profile_jit: no command given (put it after --)")
    work = args.out or tempfile.mkdtemp(prefix="fh_profile_jit_")
    os.makedirs(work, exist_ok=True)
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL)
    try:
        time.sleep(args.wait)
        if child.poll() is not None:
            raise SystemExit(f"profile_jit: the command ended within --wait {args.wait} s: give it more work")
        perf_data = os.path.join(work, "perf.data")
        subprocess.run(["perf", "record", "-q", "-o", perf_data, "-p", str(child.pid), "--", "sleep", str(args.seconds)],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if child.poll() is not None:
            raise SystemExit("profile_jit: the command ended while sampling; its code is gone: give it more work")
        mappings = executable_anonymous_mappings(child.pid)
        code = []
        for start, end in mappings:
            path = os.path.join(work, f"jit_{start:x}.bin")
            dump_mapping(child.pid, start, end, path)
            code.append((start, end, disassemble(path, start)))
    finally:
        child.kill()
        child.wait()
    shares = sample_shares(perf_data)
    in_code = 0.0
    hot = []
    for start, end, instructions in code:
        share = sum(v for a, v in shares.items() if start <= a < end)
        in_code += share
        if share < 0.5:
            continue
        print(f"mapping {start:#x} ({end - start} bytes): {share:.1f}% of samples")
        for first, last in split_functions(instructions):
            body = instructions[first:last]
            f_share = sum(shares.get(a, 0.0) for a, _ in body)
            if f_share < 0.5:
                continue
            calls = sum(text.startswith("call") for _, text in body)
            loops = sum(re.match(r"cmp\s+\$0x8,%", text) is not None for _, text in body)
            print(f"  function at {body[0][0]:#x}, {len(body)} instructions: {f_share:.1f}%, {calls} calls, "
                  f"{loops} per-lane loops")
        for k, (address, _) in enumerate(instructions):
            if address in shares:
                hot.append((shares[address], instructions, k))
        if args.out:
            with open(os.path.join(work, f"jit_{start:x}.asm"), "w") as out:
                for address, text in instructions:
                    mark = f"{shares[address]:5.2f}" if address in shares else "     "
                    out.write(f"{mark} {address:x}: {text}\n")
    print(f"{in_code:.1f}% of the samples are in run-time code (the rest: the driver, Fredholm, the kernel)")
    hot.sort(key=lambda h: -h[0])
    for share, instructions, k in hot[:args.top]:
        print(f"\n{share:.2f}% at {instructions[k][0]:#x}:")
        for address, text in instructions[max(0, k - args.context):k + 1]:
            print(f"    {address:x}: {text}")
    # perf attributes a sample to the instruction after a slow one (a `lock` atomic, a load that missed the cache).
    print("\n(a sample lands on the instruction after the one that stalled)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
