"""The reference window (planner -> MPC) as biped_msgs/ReferenceTrajectory and back.

The one message form of biped_planner.reference_window.ReferenceWindow: the reference
generator publishes it, the MPC controller reads it.
"""
import array

from biped_msgs.msg import ReferenceTrajectory
import numpy as np

from biped_planner.node_support.stamps import seconds_of
from biped_planner.reference_window import ReferenceWindow

UNBOUNDED = 1e9  # stands for +-inf in ReferenceTrajectory bounds (CDR carries inf, users read 1e9)
# ReferenceTrajectory's float64[] fields as (ReferenceWindow field, its columns): the feet first,
# then the (N, 2) arrays, which are sent clipped to +-UNBOUNDED.
REFERENCE_FEET = (('left_foot', ('left_foot_x', 'left_foot_y', 'left_foot_z')),
                  ('left_yaw', ('left_foot_yaw',)),
                  ('right_foot', ('right_foot_x', 'right_foot_y', 'right_foot_z')),
                  ('right_yaw', ('right_foot_yaw',)))
REFERENCE_PAIRS = tuple((name, (name + '_x', name + '_y')) for name in (
    'zmp', 'hip', 'left_mass', 'right_mass', 'zmp_min', 'zmp_max', 'left_landing_min',
    'left_landing_max', 'right_landing_min', 'right_landing_max'))
REFERENCE_ARRAYS = REFERENCE_FEET + REFERENCE_PAIRS
REFERENCE_COLUMNS = tuple(column for _, columns in REFERENCE_ARRAYS for column in columns)
REFERENCE_ROW_ARRAY = tuple(name for name, columns in REFERENCE_ARRAYS for _ in columns)
FIRST_PAIR_COLUMN = sum(len(columns) for _, columns in REFERENCE_FEET)
FIRST_LANDING_COLUMN = REFERENCE_COLUMNS.index('left_landing_min_x')  # landing bounds last


def reference_trajectory_msg(window, plan_id: int, dt: float, stamp,
                             plan_revision: int = 0,
                             walk_adjustments: int = 0) -> ReferenceTrajectory:
    """A ReferenceWindow as the flat arrays of biped_msgs/ReferenceTrajectory."""
    msg = ReferenceTrajectory()
    msg.header.stamp = stamp
    msg.plan_id = int(plan_id)
    msg.plan_revision = int(plan_revision)
    msg.walk_adjustments = int(walk_adjustments)
    msg.dt = float(dt)
    n = len(window.t)
    table = np.empty((len(REFERENCE_COLUMNS), n))
    row = 0
    for name, columns in REFERENCE_ARRAYS:
        table[row:row + len(columns)] = np.reshape(getattr(window, name), (n, -1)).T
        row += len(columns)
    np.clip(table[FIRST_PAIR_COLUMN:], -UNBOUNDED, UNBOUNDED, out=table[FIRST_PAIR_COLUMN:])
    # Copied as bytes: the message setters convert anything but an array.array element by
    # element (10 us a field, 36 fields a message).
    for column, values in zip(REFERENCE_COLUMNS, table):
        setattr(msg, column, array.array('d', values.tobytes()))
    msg.support = array.array('B', np.asarray(window.support, dtype=np.uint8).tobytes())
    msg.step_index = array.array('I', np.asarray(window.step_index, dtype=np.uint32).tobytes())
    return msg


def window_from_reference_msg(msg: ReferenceTrajectory):
    """biped_msgs/ReferenceTrajectory back to a ReferenceWindow (+-1e9 bounds become +-inf).

    :raises ValueError: when the arrays have different lengths or are not finite
    """
    n = len(msg.zmp_x)
    fields = [getattr(msg, column) for column in REFERENCE_COLUMNS]
    for row, values in enumerate(fields):
        if len(values) != n:
            raise ValueError(f'reference {REFERENCE_ROW_ARRAY[row]} has {len(values)} samples, '
                             f'zmp has {n}')
    # float64[] fields are array.array('d'): their buffers joined make the table in one copy
    table = np.frombuffer(b''.join(fields), dtype=float).reshape(len(fields), n).copy()
    landing = table[FIRST_LANDING_COLUMN:]  # +-inf: the leg is in stance
    landing[landing >= UNBOUNDED] = np.inf
    landing[landing <= -UNBOUNDED] = -np.inf
    valid = np.isfinite(table)
    valid[FIRST_LANDING_COLUMN:] = ~np.isnan(landing)
    if not valid.all():
        row = int(np.argmin(valid.all(axis=1)))
        raise ValueError(f'reference {REFERENCE_ROW_ARRAY[row]} is not finite')
    arrays, row = {}, 0
    for name, columns in REFERENCE_ARRAYS:
        arrays[name] = table[row] if len(columns) == 1 else table[row:row + len(columns)].T
        row += len(columns)
    support = np.asarray(msg.support, dtype=np.uint8)
    step_index = np.asarray(msg.step_index, dtype=np.int64)
    if len(support) != n or len(step_index) != n or not np.isfinite(msg.dt) or msg.dt <= 0.0:
        raise ValueError(f'reference support/step_index/dt malformed (n={n}, dt={msg.dt})')
    t0 = seconds_of(msg.header.stamp)
    return ReferenceWindow(t=t0 + msg.dt * np.arange(n), support=support, step_index=step_index,
                           **arrays)
