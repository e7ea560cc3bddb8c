"""Graph tests: a fall is recoverable, and commands that make no sense while walking are refused.

The whole graph runs (scripts/bringup.py, lockstep sim time); the test is a user: it pushes the
robot over, calls the state machine's reset (std_srvs/Trigger), and walks again.
"""
from biped_msgs.msg import CommandStatus, WalkCommand, WalkingState
from biped_tools.graph_session import GraphSession

from graph_user import GraphUser, WALKING
from ros_harness import domain_id_for_worker


def test_a_robot_pushed_over_is_reset_and_walks_ten_steps():
    with GraphSession(domain_id_for_worker(), log=print) as session:
        session.wait_until_ready()
        user = GraphUser(session)
        assert session.push(400.0, duration=0.2)
        assert session.spin_until(lambda: user.states and user.state().fallen, 60), 'no fall'
        assert user.state().phase == WalkingState.FALLEN
        assert session.wait_sim_time(1.0, 60)  # lying on the ground
        epoch = user.state().epoch
        response = user.reset()
        assert response.success, response.message
        assert session.spin_until(lambda: user.state().epoch == epoch + 1 and
                                  user.state().phase == WalkingState.IDLE, 30)
        t_reset = session.sim_time()
        assert session.wait_sim_time(2.0, 60)
        assert user.stood_since(t_reset + 0.1)  # stood up, and stands
        user.command(command=WalkCommand.START)
        assert user.wait_walking(10)
        walked = [s for s in user.states if s.epoch == epoch + 1]
        assert max(s.step_index for s in walked) >= 10
        assert not any(s.fallen for s in walked)
        assert user.stood_since(t_reset + 0.1)
        user.command(command=WalkCommand.STOP)
        assert session.spin_until(lambda: user.state().phase == WalkingState.IDLE, 60)
        assert user.stood_since(t_reset + 0.1)


def test_reset_while_walking_is_refused_and_a_reset_while_standing_walks_again():
    with GraphSession(domain_id_for_worker(), log=print) as session:
        session.wait_until_ready()
        user = GraphUser(session)
        user.command(command=WalkCommand.START)
        assert user.wait_walking(2)
        assert user.state().phase in WALKING
        t_walking = session.sim_time()
        epoch = user.state().epoch
        response = user.reset()  # the service
        assert not response.success and 'walking' in response.message
        count = len(user.statuses)
        user.command(command=WalkCommand.RESET)  # the walk command
        assert session.spin_until(lambda: any(
            s.command == WalkCommand.RESET for s in user.statuses[count:]), 15)
        refusal = next(s for s in user.statuses[count:] if s.command == WalkCommand.RESET)
        assert refusal.error_code == CommandStatus.NOT_ALLOWED and refusal.error_msg
        assert session.wait_sim_time(2.0, 60)
        assert user.state().phase in WALKING and user.state().epoch == epoch
        assert not user.state().fallen and user.stood_since(t_walking)
        user.command(command=WalkCommand.STOP)
        assert session.spin_until(lambda: user.state().phase == WalkingState.IDLE, 60)
        # standing: a reset is allowed, and the robot walks again after it
        response = user.reset()
        assert response.success, response.message
        assert session.spin_until(lambda: user.state().epoch == epoch + 1, 30)
        t_reset = session.sim_time()
        user.command(command=WalkCommand.START)
        assert user.wait_walking(4)
        assert not user.state().fallen and user.stood_since(t_reset)
