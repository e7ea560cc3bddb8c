"""One trial of a scenario: a fresh node graph with a bag, a progress line, a JSON result."""
from contextlib import contextmanager
from dataclasses import dataclass, field
import json
import math
from pathlib import Path
import shutil
import threading
import time
from typing import Callable, Dict, List, Optional

from biped_msgs.msg import WalkCommand, WalkingState

from biped_tools.graph_session import GraphSession, IDLE


@dataclass
class Trial:
    """Where and how one trial runs.

    :param scenario: scenario name (disk, omni, push, terrain, goal)
    :param model: controller model, 'three_mass' or 'lipm'
    :param setting: the swept value or case, part of the output path (e.g. '0.15')
    :param out: root output directory; the trial writes to out/scenario/model/setting/
    :param domain_id: ROS domain of this trial's graph
    :param record: write a rosbag2 of the run
    :param overrides: extra node parameters, {node: ['name:=value', ...]}
    :param log: progress and messages
    :param node_log: the graph's node log lines (bring-up prefixes them), besides the trial's
        nodes.log; not printed by default
    """

    scenario: str
    model: str
    setting: str
    out: Path
    domain_id: int
    record: bool = True
    overrides: Dict[str, List[str]] = field(default_factory=dict)
    log: Callable[[str], None] = print
    node_log: Callable[[str], None] = lambda line: None

    @property
    def directory(self) -> Path:
        return Path(self.out) / self.scenario / self.model / self.setting

    @property
    def label(self) -> str:
        return f'{self.scenario} {self.model} {self.setting}'


# The paper sweeps steps up to 0.25 m (disk) and commands up to 0.2 m x scale (omni): the
# planner's teleop limit (0.2 m in its config) must not clip them; 0.3 m is the command bound.
SWEEP_LIMITS = {'footstep_planner': ['teleop.max_step_length:=0.3']}

# A scripted walk starts at a stated sim time, the same in every run: started at "now + lead",
# the robot stood for a time that depended on how fast the graph came up, and a run near a limit
# changed its outcome (a push trial withstood 140 N in one run and 120 N in the next).
STATED_START = 10.0  # s of sim time
# The lockstep clock holds here (simulator hold_at) until the trial's graph is ready: how long
# the runner took to see that (discovery, on the wall clock) then moves nothing in sim time. It
# was ready at 3-11 s of a running clock, and after 8 s a walk started at 20 s instead of 10 s:
# another trial (an omni setting fell in the first run and walked in its two repeats).
HOLD_AT = 2.0  # s of sim time
# s of sim time the lockstep clock may run ahead of what the trial's runner has acted on
# (simulator paced_by): its decisions, stated at least this far ahead, meet their stated times
# however slowly the runner runs (a loaded runner was seconds behind the clock)
PACE_LEAD = 0.1
START_MARGIN = 2.0   # s of sim time the command needs before its start
# A graph that does not come up in time is started once more before the trial fails: under
# heavy load one graph in about 26 did not, and it stopped a whole table run.
GRAPH_ATTEMPTS = 2
# Every node's log lines of a trial, kept beside its result: a run that differs from its
# repeats can be read afterwards (printed too with --node-log)
NODE_LOG = 'nodes.log'


def stated_start_time(now: float) -> float:
    """STATED_START, or the next multiple of it when the clock (now, s) is too close to it."""
    return STATED_START * max(1, math.ceil((now + START_MARGIN) / STATED_START))


def stated_start(session, trial: 'Trial') -> float:
    """:return: stated_start_time of the session's clock (logged when it is not STATED_START:
    such a run may differ from the others)"""
    earliest = session.sim_time() + START_MARGIN
    start = stated_start_time(session.sim_time())
    if start != STATED_START:
        trial.log(f'[{trial.label}] the graph was ready at t={earliest - START_MARGIN:.2f} s: '
                  f'the walk starts at t={start:.1f} s, not {STATED_START:.1f} s')
    return start


class TrialFactory:
    """Trials of one model under one output root, each on the next ROS domain of a block of 10
    (a fresh domain per graph keeps the previous graph's discovery data out of the next)."""

    def __init__(self, out: Path, model: str, domain_base: int, record: bool = True,
                 log: Callable[[str], None] = print,
                 overrides: Optional[Dict[str, List[str]]] = None,
                 node_log: Optional[Callable[[str], None]] = None) -> None:
        """:param node_log: where the nodes' log lines go; None: dropped"""
        self.out, self.model, self.domain_base = out, model, domain_base
        self.record, self.log, self.node_log = record, log, node_log
        self.overrides = {node: list(values) for node, values in (overrides or {}).items()}
        self.count = 0

    def __call__(self, scenario: str, setting: str) -> Trial:
        self.count += 1
        return Trial(scenario, self.model, setting, self.out,
                     self.domain_base + self.count % 10, record=self.record,
                     overrides={node: list(values) for node, values in self.overrides.items()},
                     log=self.log, **({} if self.node_log is None else
                                      {'node_log': self.node_log}))


def graph_overrides(model: str, start=(0.0, 0.0, 0.0), timing: Optional[tuple] = None,
                    extra: Optional[Dict[str, List[str]]] = None) -> Dict[str, List[str]]:
    """Node parameters of a scenario's graph: {node: ['name:=value', ...]}.

    :param model: the controller's model, 'three_mass' or 'lipm'
    :param start: the robot's start pose in the simulator (x m, y m, yaw rad)
    :param timing: (single, double support) of the gait in s; None: the configured one
    :param extra: more node parameters, given first
    """
    overrides = {node: list(values) for node, values in (extra or {}).items()}
    overrides.setdefault('mpc_controller', []).append(f'model:={model}')
    overrides.setdefault('simulator', []).extend(
        [f'start_x:={start[0]}', f'start_y:={start[1]}', f'start_yaw:={start[2]}'])
    if timing is not None:
        for node in ('state_machine', 'footstep_planner'):
            overrides.setdefault(node, []).extend(
                [f'single_support:={timing[0]}', f'double_support:={timing[1]}'])
    return overrides


def sample_at(samples, t: float):
    """The last of the (t, ...) samples stamped at or before t (s), None when none is."""
    before = [sample for sample in samples if sample[0] <= t + 1e-9]
    return before[-1] if before else None


def fresh_bag_dir(directory: Path) -> Path:
    """directory/bag, a previous run's bag there removed (the recorder creates it anew)."""
    bag = Path(directory) / 'bag'
    if bag.exists():
        shutil.rmtree(bag)
    return bag


@contextmanager
def graph_for(trial: Trial, timing: Optional[tuple] = None, start=(0.0, 0.0, 0.0),
              extra: Optional[Dict[str, List[str]]] = None):
    """A started graph for the trial: its model, start pose and gait timing (single, double
    support in s; None: the configured one), extra node parameters, recording to its bag."""
    directory = trial.directory
    directory.mkdir(parents=True, exist_ok=True)
    bag = fresh_bag_dir(directory)
    given = {node: list(values) for node, values in trial.overrides.items()}
    for node, values in (extra or {}).items():
        given.setdefault(node, []).extend(values)
    overrides = graph_overrides(trial.model, start, timing, given)
    # one reader thread per node process writes here; a text file is not thread-safe, and
    # interleaved writes once left a multibyte character split (a test could not decode it)
    lock = threading.Lock()
    with open(directory / NODE_LOG, 'w', encoding='utf-8') as node_log_file:
        def node_log(line: str) -> None:
            with lock:
                try:
                    node_log_file.write(line + '\n')
                except ValueError:  # a reader thread that outlived the graph's stop: closed
                    pass
            trial.node_log(line)
        yield from _started_graph(trial, directory, bag, overrides, node_log)


def _started_graph(trial: Trial, directory: Path, bag: Path, overrides: Dict[str, List[str]],
                   node_log: Callable[[str], None]):
    for attempt in range(1, GRAPH_ATTEMPTS + 1):
        with GraphSession(trial.domain_id, bag_dir=bag if trial.record else None,
                          overrides=overrides, hold_at=HOLD_AT, pace_lead=PACE_LEAD,
                          log=node_log) as session:
            try:
                session.wait_until_ready()
                session.resume_clock()
            except TimeoutError as error:
                if attempt == GRAPH_ATTEMPTS:
                    raise
                trial.log(f'[{trial.label}] {error}: the graph is started again')
                bag = fresh_bag_dir(directory)
                continue
            yield session
            return


class Progress:
    """A progress line every few wall seconds: sim time, speed, pelvis, step, what is going on."""

    def __init__(self, trial: Trial, every: float = 5.0) -> None:
        self.trial, self.every = trial, every
        self.wall0 = time.monotonic()
        self.last = self.wall0
        self.sim0 = None

    def __call__(self, session: GraphSession, note: str = '') -> None:
        now = time.monotonic()
        if session.series.pelvis and self.sim0 is None:
            self.sim0 = session.sim_time()
        if now - self.last < self.every or self.sim0 is None:
            return
        self.last = now
        t = session.sim_time()
        p = session.series.pelvis[-1]
        step = session.series.states[-1][2] if session.series.states else 0
        speed = (t - self.sim0) / (now - self.wall0)
        self.trial.log(f'  [{self.trial.label}] sim {t:6.1f} s ({speed:.1f}x real time), '
                       f'pelvis ({p[1]:+.2f}, {p[2]:+.2f}), step {step} {note}')


def drive(session: GraphSession, on_time: Callable[[float], bool], sim_duration: float,
          progress: Progress, note: Callable[[], str] = lambda: '') -> bool:
    """Call on_time(t) at each new sim time until it returns True (-> True), the robot falls
    or sim_duration s of sim time pass (-> False). Wall timeout: 20x the sim duration + 60 s.

    While the session holds a paced clock (pace_limit set), on_time is called at every turn of
    the executor, not only at a new sim time: the clock waits for on_time's decision, and the
    wall-time fallback of that decision (a message that never comes) must run while it waits."""
    end = session.sim_time() + sim_duration
    state = {'t': -1.0, 'done': False}

    def tick() -> bool:
        progress(session, note())
        t = session.sim_time()
        if t != state['t'] or session.pace_limit is not None:
            state['t'] = t
            state['done'] = bool(on_time(t))
        return state['done'] or session.fallen() or t >= end
    session.spin_until(tick, 20.0 * sim_duration + 60.0)
    return state['done'] and not session.fallen()


STOP_LEAD = 0.5  # s: a stated STOP is sent this long before its time (the state machine holds it)
# s of sim time after the sample that ends a trial's walk (a terrain crossed) at which its STOP
# applies: the runner sees that sample some wall time later, and a STOP stated by the sample's
# stamp ends the walk at the same sim time on a quiet and a loaded machine
STOP_AFTER_ARRIVAL = 1.0


def stop_walking(session: GraphSession, timeout_sim: float = 5.0,
                 at: Optional[float] = None) -> bool:
    """STOP, then wait for Idle (True) or a fall (False).

    :param at: sim time the stop applies at (WalkCommand.start_time), so that a trial ends the
        same way on a quiet and a loaded machine; None: when it arrives
    """
    if session.fallen():
        return False
    session.send_command(command=WalkCommand.STOP, start_time=0.0 if at is None else at)
    end = max(session.sim_time(), at or 0.0) + timeout_sim
    session.spin_until(lambda: session.phase() == IDLE or session.fallen() or
                       session.sim_time() >= end, 20.0 * timeout_sim + 30.0)
    session.wait_sim_time(0.5, 30.0)
    return session.phase() == IDLE and not session.fallen()


def request_push(session: GraphSession, force: float, fx: float, fy: float, at: float,
                 duration: float) -> Optional[str]:
    """Ask the simulator for a pelvis push (fx, fy) (N) at sim time at; force, its magnitude
    as the trial's schedule names it (N), is for the messages.

    :return: None when scheduled; the error when the answer was lost (the push may have been
        scheduled, so a trial watches it as if it was and asks for none after it)
    :raises RuntimeError: the simulator refused it
    """
    try:
        applied = session.push(fx, fy, duration=duration, at=at)
    except TimeoutError as error:
        return str(error)
    if not applied:
        raise RuntimeError(f'push of {force} N at t={at:.2f} s refused')
    return None


def fall_time(session: GraphSession) -> Optional[float]:
    """Sim time the state machine saw the fall: the start of its FALLEN phase (stamp -
    time_in_phase). A robot that fell while the graph came up, before this runner's first
    sample, gets its own fall time, not the time the runner happened to look (which depends on
    the load)."""
    for stamp, phase, _, fallen, _, _, in_phase in session.series.states:
        if fallen:
            return stamp - in_phase if phase == WalkingState.FALLEN else stamp
    return None


def base_result(trial: Trial, session: GraphSession, wall0: float, sim0: float) -> dict:
    """What every trial reports: outcome, fall, durations, MPC solve times, the bag."""
    solve = sorted(session.series.solve_times)
    t_fall = fall_time(session)
    return {
        'scenario': trial.scenario, 'model': trial.model, 'setting': trial.setting,
        'fallen': t_fall is not None,
        'fall_time_s': None if t_fall is None else round(t_fall - sim0, 2),
        # the fall's own sim time: the same in every run of a trial (sim0 is when the runner
        # happened to look, which depends on the load)
        'fall_sim_time_s': None if t_fall is None else round(t_fall, 3),
        'simulated_s': round(session.sim_time() - sim0, 2),
        'wall_s': round(time.monotonic() - wall0, 1),
        'max_tilt_deg': round(math.degrees(max(p[4] for p in session.series.pelvis)), 2),
        'mpc_solve_median_us': round(1e6 * solve[len(solve) // 2], 1) if solve else None,
        'bag': str(trial.directory / 'bag') if trial.record else None,
    }


def write_result(trial: Trial, result: dict) -> dict:
    """result.json in the trial's directory, and a one-line verdict."""
    (trial.directory / 'result.json').write_text(json.dumps(result, indent=2))
    verdict = 'SUCCESS' if result['success'] else 'FAILED'
    trial.log(f'[{trial.label}] {verdict}: ' + ', '.join(
        f'{k} {v}' for k, v in result.items() if k in trial_summary_keys(result)))
    return result


def trial_summary_keys(result: dict):
    """The scalar outcomes worth a progress line (not the lists, paths and labels)."""
    return [k for k, v in result.items() if not isinstance(v, (list, dict)) and k not in (
        'scenario', 'model', 'setting', 'bag', 'success', 'mpc_solve_median_us')]
