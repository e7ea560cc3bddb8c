"""Camera frames of a simulation written as numbered PNG files, and their assembly into a GIF.

Frames go to disk as they are taken, so a run that is stopped or killed keeps what it filmed;
the GIF is made afterwards from the directory.
"""
import math
from pathlib import Path
from typing import Callable

import numpy as np

from biped_sim.errors import ConfigError

FRAME_PATTERN = 'frame_%06d.png'
FPS_RANGE = (0.1, 100.0)  # frames per second of simulated time


class FrameRecorder:
    """Takes a frame whenever simulated time reaches the next multiple of 1 / fps.

    :param directory: where the PNG frames go (created; existing frames are replaced)
    :param fps: frames per second of simulated time, in FPS_RANGE
    """

    def __init__(self, directory: Path, fps: float) -> None:
        if not (isinstance(fps, (int, float)) and math.isfinite(fps)
                and FPS_RANGE[0] <= fps <= FPS_RANGE[1]):
            raise ConfigError(f'FrameRecorder.fps = {fps!r} must be in {list(FPS_RANGE)}')
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        for old in self.directory.glob('frame_*.png'):
            old.unlink()
        self.period = 1.0 / fps
        self.count = 0
        self._next_time = None

    def maybe_capture(self, time: float, render: Callable[[], np.ndarray]) -> bool:
        """Render and save a frame if one is due at sim time `time` (s).

        :param render: returns an (height, width, 3) uint8 RGB image
        :return: whether a frame was written
        """
        if self._next_time is not None and time < self._next_time - 1e-9:
            return False
        from PIL import Image
        Image.fromarray(np.asarray(render(), dtype=np.uint8)).save(
            self.directory / (FRAME_PATTERN % self.count))
        self.count += 1
        self._next_time = (time if self._next_time is None else self._next_time) + self.period
        return True


def frames_to_gif(directory: Path, out: Path, fps: float) -> int:
    """Assemble the PNG frames of directory, in order, into an animated GIF at fps.

    :return: the number of frames
    :raises ConfigError: if the directory holds no frames
    """
    from PIL import Image
    paths = sorted(Path(directory).glob('frame_*.png'))
    if not paths:
        raise ConfigError(f'no frames in {directory}')
    frames = [Image.open(path).convert('P', palette=Image.Palette.ADAPTIVE) for path in paths]
    frames[0].save(out, save_all=True, append_images=frames[1:], loop=0,
                   duration=int(round(1000.0 / fps)), optimize=False)
    return len(frames)
