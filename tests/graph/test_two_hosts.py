"""Two hosts: the simulator (the robot) and the rest of the graph (the workstation) in two
network namespaces joined by a veth pair, DDS discovery limited to that link.

Shared memory is off (FASTDDS_BUILTIN_TRANSPORTS=UDPv4: the namespaces share /dev/shm, and
DDS would otherwise use it between the "hosts"), so every message crosses the link over UDP.
Needs root for `ip netns` (skipped without it).
"""
import json
import os
from pathlib import Path
import signal
import subprocess
import sys

import pytest

from ros_harness import domain_id_for_worker

ROOT = Path(__file__).resolve().parents[2]
CLIENT = Path(__file__).with_name('two_host_client.py')
WORKSTATION_NODES = ['map_server', 'state_machine', 'footstep_planner', 'reference_generator',
                     'mpc_controller']
STEPS = 10


def ip(*args) -> None:
    subprocess.run(['ip', *args], check=True, capture_output=True, text=True)


class TwoHosts:
    """Two namespaces and a veth pair between them, with addresses of their own."""

    def __init__(self, tag: str, subnet: int) -> None:
        self.robot, self.station = f'biped_robot_{tag}', f'biped_station_{tag}'
        self.addresses = {self.robot: f'10.213.{subnet}.1', self.station: f'10.213.{subnet}.2'}
        self.links = {self.robot: f'bvr{tag}', self.station: f'bvs{tag}'}

    def __enter__(self) -> 'TwoHosts':
        ip('netns', 'add', self.robot)
        ip('netns', 'add', self.station)
        ip('link', 'add', self.links[self.robot], 'type', 'veth', 'peer', 'name',
           self.links[self.station])
        for host in (self.robot, self.station):
            link = self.links[host]
            ip('link', 'set', link, 'netns', host)
            ip('-n', host, 'addr', 'add', f'{self.addresses[host]}/30', 'dev', link)
            ip('-n', host, 'link', 'set', link, 'up')
            ip('-n', host, 'link', 'set', 'lo', 'up')
            ip('-n', host, 'route', 'add', '224.0.0.0/4', 'dev', link)  # DDS discovery
        return self

    def environment(self, host: str, domain_id: int) -> dict:
        peer = self.station if host == self.robot else self.robot
        return dict(os.environ, ROS_DOMAIN_ID=str(domain_id),
                    ROS_AUTOMATIC_DISCOVERY_RANGE='SUBNET',
                    ROS_STATIC_PEERS=self.addresses[peer],
                    FASTDDS_BUILTIN_TRANSPORTS='UDPv4', PYTHONUNBUFFERED='1')

    def run(self, host: str, domain_id: int, args, **kwargs) -> subprocess.Popen:
        return subprocess.Popen(['ip', 'netns', 'exec', host, *args],
                                env=self.environment(host, domain_id), **kwargs)

    def __exit__(self, *exc) -> bool:
        for host in (self.robot, self.station):
            pids = subprocess.run(['ip', 'netns', 'pids', host], capture_output=True,
                                  text=True).stdout.split()
            for pid in pids:
                try:
                    os.kill(int(pid), signal.SIGKILL)
                except ProcessLookupError:
                    pass
            subprocess.run(['ip', 'netns', 'del', host], capture_output=True)
        return False


def namespaces_available() -> bool:
    if os.geteuid() != 0:
        return False
    probe = f'biped_probe_{os.getpid()}'
    made = subprocess.run(['ip', 'netns', 'add', probe], capture_output=True).returncode == 0
    if made:
        subprocess.run(['ip', 'netns', 'del', probe], capture_output=True)
    return made


@pytest.mark.skipif(not namespaces_available(), reason='needs root and ip netns')
def test_the_graph_walks_ten_steps_with_the_simulator_on_another_host():
    domain = domain_id_for_worker()
    tag = f'{os.getpid() % 100000}'
    bringup = [sys.executable, str(ROOT / 'scripts' / 'bringup.py'), '--sim-time',
               '--domain-id', str(domain), '--timeout', '120']
    with TwoHosts(tag, domain % 200) as hosts:
        robot = hosts.run(hosts.robot, domain, bringup + ['--nodes', 'simulator'])
        station = hosts.run(hosts.station, domain,
                            bringup + ['--nodes', *WORKSTATION_NODES])
        try:
            client = hosts.run(hosts.station, domain,
                               [sys.executable, str(CLIENT), str(STEPS), '240'],
                               stdout=subprocess.PIPE, text=True)
            output, _ = client.communicate(timeout=300)
        finally:
            for process in (station, robot):
                process.send_signal(signal.SIGINT)
            for process in (station, robot):
                try:
                    process.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
    result = json.loads(output.strip().splitlines()[-1])
    print('two hosts:', result)
    assert result['ready'], 'the graph did not come up across the link'
    # the client's whole record in the message: a failure says how far and how fast it went
    assert result['walked'] and result['steps'] >= STEPS, result
    assert not result['fallen'], result
