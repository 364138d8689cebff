"""The work list of a distributed render: which sample ranges of which frames, and where each frame's image goes."""
import re
from dataclasses import dataclass
from typing import List, Optional, Tuple


class UsageError(Exception):
    """A bad command line or input file: main prints it as one line and exits 2."""


@dataclass(frozen=True)
class Chunk:
    index: int            # over the whole run, 0-based, in submission order
    frame: Optional[int]  # None for a single image
    time: Optional[str]   # --time for this frame (repr of a double, so it round-trips exactly), None for a still
    first: int            # sample indices [first, end) of every pixel
    end: int
    crop: Optional[Tuple[int, int, int, int]] = None  # pixels x0, y0, x1, y1 (--tiles), None for the whole image

    def describe(self):
        where = f"frame {self.frame}, " if self.frame is not None else ""
        if self.crop is not None:
            where += "crop {},{},{},{}, ".format(*self.crop)
        return f"chunk {self.index} ({where}samples {self.first}:{self.end})"


def split_samples(spp, chunks):
    """[0, spp) cut into `chunks` contiguous ranges [k*spp//chunks, (k+1)*spp//chunks), empty ones left out."""
    if spp < 1:
        raise UsageError(f"--spp {spp} must be at least 1")
    if chunks < 1:
        raise UsageError(f"--chunks {chunks} must be at least 1")
    ranges = [(k * spp // chunks, (k + 1) * spp // chunks) for k in range(chunks)]
    return [(a, b) for a, b in ranges if b > a]


def parse_tiles(text, width, height):
    """'COLSxROWS' as the crops (x0, y0, x1, y1) that tile a width x height image, row by row; None for '1x1'."""
    match = re.fullmatch(r"(\d+)x(\d+)", text)
    if not match:
        raise UsageError(f"--tiles '{text}' is not COLSxROWS (e.g. 4x4)")
    cols, rows = int(match.group(1)), int(match.group(2))
    if not (1 <= cols <= width and 1 <= rows <= height):
        raise UsageError(f"--tiles '{text}' needs 1 to {width} columns and 1 to {height} rows for a "
                         f"{width}x{height} image")
    if cols == rows == 1:
        return None
    xs = [c * width // cols for c in range(cols + 1)]
    ys = [r * height // rows for r in range(rows + 1)]
    return [(xs[c], ys[r], xs[c + 1], ys[r + 1]) for r in range(rows) for c in range(cols)]


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


def make_chunks(spp, chunks, frames=None, fps=24.0, crops=None):
    """Every chunk of the run: one set of sample ranges per frame (frames: (first, last) or None for a still) and
    per crop (crops: from parse_tiles, None for the whole image)."""
    ranges = split_samples(spp, chunks)
    frame_list = [None] if frames is None else list(range(frames[0], frames[1] + 1))
    work: List[Chunk] = []
    for frame in frame_list:
        # repr() of the same double fredholm computes for --frames (double(f) / fps), so the pose is bit-identical.
        time = None if frame is None else repr(frame / fps)
        for crop in crops or [None]:
            for first, end in ranges:
                work.append(Chunk(len(work), frame, time, first, end, crop))
    return work
