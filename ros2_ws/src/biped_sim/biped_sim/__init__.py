"""Simulator backends of the biped stack: PyBullet humanoid and the three-mass model plant."""
