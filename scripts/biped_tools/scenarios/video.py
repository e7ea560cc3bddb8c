"""A short clip of one scenario from the simulator's camera: the simulator node writes PNG
frames (parameter camera.frames_dir) while the scenario runs; they become an animated GIF."""
from pathlib import Path

from biped_tools.scenarios import disk, omni, push, push_directions, terrain


def run_video(args, make_trial) -> int:
    """Run args.which (a short setting) with camera frames on; write the GIF beside them."""
    from biped_sim.frame_recorder import frames_to_gif
    trial = make_trial(args.which, 'video')
    frames = trial.directory / 'frames'
    trial.overrides = {'simulator': [f'camera.frames_dir:={frames}',
                                     f'camera.fps:={args.fps}']}
    if args.which == 'disk':
        disk.run(trial, 0.15, laps=0.25)
    elif args.which == 'omni':
        omni.run(trial, 1.0, duration=24.0)
    elif args.which == 'push':
        push.run(trial, [80.0, 100.0, 120.0])
    elif args.which == 'push-adjusted':  # the graph test's push, step adjustment on
        push_directions.run(trial, 270.0, 'early_single_left', 'in_place', [140.0], True,
                            interval=3.0, plot=True)
    else:
        terrain.run(trial, 400, seed=1, side=2.0)
    out = Path(trial.directory) / f'{args.which}_{trial.model}.gif'
    count = frames_to_gif(frames, out, args.fps)
    trial.log(f'[video] {count} frames ({count / args.fps:.0f} s of sim time) -> {out}')
    return 0
