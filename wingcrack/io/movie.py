"""growth.gif or growth.mp4 written from its frames (io.frames.Frame), at
FPS: the GIF by Pillow, the MP4 by ffmpeg's libx264 from the RGBA
pixels on its standard input (the options of matplotlib's FFMpegWriter),
through a temporary file renamed over the old one (io.atomic)."""
from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

from .atomic import replacing

#: frames per second
FPS = 4


def animation_format() -> str:
    """"mp4" when ffmpeg is on PATH, else "gif"."""
    return "mp4" if shutil.which("ffmpeg") else "gif"


def write(path: Path, fmt: str, frames: list) -> Path:
    """Write `frames` (one size) to `path`."""
    # the temporary file keeps the suffix: Pillow's format goes by it
    with replacing(path, Path(path).suffix) as tmp:
        if fmt == "gif":
            images = [f.image() for f in frames]
            # the frames' one palette as they have it (Pillow would otherwise cut each to the colours it uses,
            # and compare frames of different palettes colour by colour)
            images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=int(1000 / FPS),
                           loop=0, optimize=False)
        else:
            _ffmpeg(tmp, frames, frames[0].size, FPS)
    return Path(path)


def _ffmpeg(path: Path, frames: list, size: tuple, fps: int) -> None:
    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        raise RuntimeError("ffmpeg is not on PATH (it was when the animation's format was chosen)")
    w, h = size
    command = [ffmpeg, "-f", "rawvideo", "-vcodec", "rawvideo", "-s", f"{w}x{h}", "-pix_fmt", "rgba", "-r", str(fps),
               "-loglevel", "error", "-i", "pipe:", "-vcodec", "libx264", "-pix_fmt", "yuv420p", "-y", str(path)]
    # its messages to a file: a pipe that fills while the frames go in would block both
    with tempfile.TemporaryFile() as said:
        proc = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=said)
        try:
            for frame in frames:
                proc.stdin.write(frame.rgba())
            proc.stdin.close()
        except BrokenPipeError:
            pass   # ffmpeg stopped: its status and message say why
        finally:
            status = proc.wait()
        said.seek(0)
        err = said.read().decode(errors="replace")
    if status != 0:
        raise RuntimeError(f"ffmpeg failed (exit {status}): {' '.join(err.split())[:300]}")
