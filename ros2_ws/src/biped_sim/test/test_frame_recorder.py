"""Frame recorder: frames at the requested sim-time rate, written as PNG, assembled to a GIF."""
import numpy as np
import pytest

from biped_sim.errors import ConfigError
from biped_sim.frame_recorder import frames_to_gif, FrameRecorder


def test_frames_are_taken_at_the_requested_sim_rate_and_make_a_gif(tmp_path):
    recorder = FrameRecorder(tmp_path / 'frames', fps=10.0)
    shades = []

    def render():
        shade = len(shades) * 20
        shades.append(shade)
        return np.full((24, 32, 3), shade, dtype=np.uint8)
    taken = [t for t in np.arange(0.0, 1.0, 0.02) if recorder.maybe_capture(round(t, 2), render)]
    np.testing.assert_allclose(taken, np.arange(0.0, 1.0, 0.1), atol=1e-9)
    assert len(list((tmp_path / 'frames').glob('frame_*.png'))) == 10
    out = tmp_path / 'clip.gif'
    assert frames_to_gif(tmp_path / 'frames', out, fps=10.0) == 10
    from PIL import Image
    with Image.open(out) as gif:
        assert gif.n_frames == 10 and gif.size == (32, 24)
        gif.seek(3)
        assert np.asarray(gif.convert('RGB'))[0, 0, 0] == pytest.approx(60, abs=2)
        assert gif.info['duration'] == 100


def test_bad_rates_and_empty_directories_are_errors(tmp_path):
    for fps in (0.0, -1.0, float('nan'), 1000.0):
        with pytest.raises(ConfigError, match='fps'):
            FrameRecorder(tmp_path, fps)
    with pytest.raises(ConfigError, match='no frames'):
        frames_to_gif(tmp_path, tmp_path / 'x.gif', 10.0)
