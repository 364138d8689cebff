"""The work list of a distributed render: which sample ranges of which frames, and where each frame's image goes."""
import re
from dataclasses import dataclass
from typing import List, Optional


class UsageError(Exception):
    """A bad command line or input file: main prints it as one line and exits 2."""


@dataclass(frozen=True)
class Chunk:
    index: int            # over the whole run, 0-based, in submission order
    frame: Optional[int]  # None for a single image
    time: Optional[str]   # --time for this frame (repr of a double, so it round-trips exactly), None for a still
    first: int            # sample indices [first, end) of every pixel
    end: int

    def describe(self):
        where = f"frame {self.frame}, " if self.frame is not None else ""
        return f"chunk {self.index} ({where}samples {self.first}:{self.end})"


def split_samples(spp, chunks):
    """[0, spp) cut into `chunks` contiguous ranges [k*spp//chunks, (k+1)*spp//chunks), empty ones left out."""
    if spp < 1:
        raise UsageError(f"--spp {spp} must be at least 1")
    if chunks < 1:
        raise UsageError(f"--chunks {chunks} must be at least 1")
    ranges = [(k * spp // chunks, (k + 1) * spp // chunks) for k in range(chunks)]
    return [(a, b) for a, b in ranges if b > a]


def parse_frames(text):
    """'A:B' (inclusive, as fredholm render --frames) or 'A' as (first, last)."""
    match = re.fullmatch(r"(\d+)(?::(\d+))?", text)
    if not match:
        raise UsageError(f"--frames '{text}' is not A:B (frame numbers)")
    first = int(match.group(1))
    last = int(match.group(2)) if match.group(2) is not None else first
    if last < first:
        raise UsageError(f"--frames '{text}' needs A <= B")
    return first, last


def name_frame_file(pattern, frame):
    """The file of `frame`: the last run of '#' in the file name replaced by the zero-padded number (as fredholm)."""
    head, sep, name = pattern.rpartition("/")
    end = name.rfind("#")
    if end < 0:
        raise UsageError(f"{pattern} has no # for the frame number (e.g. out_####.exr)")
    begin = end
    while begin > 0 and name[begin - 1] == "#":
        begin -= 1
    number = str(frame).rjust(end + 1 - begin, "0")
    return head + sep + name[:begin] + number + name[end + 1:]


def make_chunks(spp, chunks, frames=None, fps=24.0):
    """Every chunk of the run: one set of sample ranges per frame (frames: (first, last) or None for a still)."""
    ranges = split_samples(spp, chunks)
    frame_list = [None] if frames is None else list(range(frames[0], frames[1] + 1))
    work: List[Chunk] = []
    for frame in frame_list:
        # repr() of the same double fredholm computes for --frames (double(f) / fps), so the pose is bit-identical.
        time = None if frame is None else repr(frame / fps)
        for first, end in ranges:
            work.append(Chunk(len(work), frame, time, first, end))
    return work
