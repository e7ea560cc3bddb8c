"""The summary's independent units: the same domains for any number of jobs, results assembled
per model as the sequential run gives them."""
import pytest

from biped_tools.scenarios import summary
from biped_tools.scenarios.terrain import TILE_AREAS_CM2


def test_every_unit_has_its_own_block_of_domains():
    units = summary.units_of(('lipm', 'three_mass'), 50)
    assert len(units) == 2 * (4 + len(TILE_AREAS_CM2))
    bases = [u.domain_base for u in units]
    assert bases == sorted(bases) and len(set(bases)) == len(bases)
    assert all(b - a == summary.UNIT_DOMAINS for a, b in zip(bases, bases[1:]))
    assert bases[-1] + summary.UNIT_DOMAINS - 1 <= summary.MAX_DOMAIN_ID


def test_domains_past_the_dds_limit_are_refused():
    with pytest.raises(ValueError, match='start at'):
        summary.units_of(('lipm', 'three_mass'), 120)


@pytest.mark.parametrize('domain', [-1, 224, 230])
def test_a_scenario_on_domains_past_the_dds_limit_is_refused_before_it_starts(domain, capsys):
    """A trial cycles through 10 domains from --domain-id: past 232 Fast DDS could not open
    its ports, and the runs after the first failed one by one (a user's sweep on 230)."""
    from biped_tools.scenarios.command import main
    with pytest.raises(SystemExit) as exit_info:
        main(['push', '--model', 'three_mass', '--domain-id', str(domain), '--no-bag'])
    assert exit_info.value.code == 2
    assert f'--domain-id {domain}' in capsys.readouterr().err


def test_the_units_results_make_each_models_results(tmp_path, monkeypatch):
    def fake(unit, out, seeds, record, log):
        if unit.scenario == 'terrain':
            return {'runs': [{'tile_area_cm2': unit.tile_area, 'seed': s,
                              'success': unit.tile_area == 100.0,
                              'terrain_fraction_crossed': 0.5} for s in seeds]}
        return {'scenario': unit.scenario, 'model': unit.model, 'domain': unit.domain_base}
    monkeypatch.setattr(summary, 'run_unit', fake)
    per_model = summary.run_models(tmp_path, ('lipm', 'three_mass'), 50, [1, 2], jobs=1)
    assert per_model['three_mass']['push'] == {'scenario': 'push', 'model': 'three_mass',
                                               'domain': 50 + 10 * (7 + 2)}
    terrain = per_model['lipm']['terrain']
    assert len(terrain['runs']) == 2 * len(TILE_AREAS_CM2)
    assert terrain['success_fraction'] == pytest.approx(1 / len(TILE_AREAS_CM2))
    assert (tmp_path / 'lipm_results.json').exists()


def test_parameters_given_with_p_reach_every_trial_of_a_scenario(tmp_path):
    from biped_tools.scenarios.command import build_parser, trials_for
    args = build_parser().parse_args([
        'terrain', '--out', str(tmp_path), '-p', 'mpc_controller:balance:=stabilizer',
        '-p', 'simulator:sole_contact_stiffness:=0.0', '-p', 'mpc_controller:tilt_gain:=0.1'])
    trials = trials_for(args, 'three_mass')
    first, second = trials('terrain', 'a'), trials('terrain', 'b')
    for trial in (first, second):
        assert trial.overrides == {'mpc_controller': ['balance:=stabilizer', 'tilt_gain:=0.1'],
                                   'simulator': ['sole_contact_stiffness:=0.0']}
    first.overrides['simulator'].append('gui:=true')  # a trial's overrides are its own
    assert second.overrides['simulator'] == ['sole_contact_stiffness:=0.0']


def test_node_logs_are_printed_with_node_log_and_dropped_without(capsys, tmp_path):
    from biped_tools.scenarios.command import build_parser, trials_for
    for argv, shown in ((['disk', '--out', str(tmp_path)], False),
                        (['disk', '--out', str(tmp_path), '--node-log'], True)):
        trial = trials_for(build_parser().parse_args(argv), 'lipm')('disk', '0.15')
        trial.node_log('[reference_generator] [INFO] plan 1: built')
        assert ('plan 1: built' in capsys.readouterr().out) == shown


def test_the_summary_refuses_p_rather_than_ignoring_it(capsys):
    from biped_tools.scenarios.command import main
    with pytest.raises(SystemExit) as exit_info:
        main(['summary', '--no-bag', '-p', 'mpc_controller:balance:=stabilizer'])
    assert exit_info.value.code == 2
    assert 'summary does not take -p' in capsys.readouterr().err


def test_a_malformed_p_is_refused_before_any_trial_starts(capsys):
    from biped_tools.scenarios.command import main
    with pytest.raises(SystemExit) as exit_info:
        main(['terrain', '--no-bag', '-p', 'balance=stabilizer'])
    assert exit_info.value.code == 2
    assert 'expected node:param:=value' in capsys.readouterr().err


@pytest.mark.parametrize('heights', [('0.03', '0.02'), ('-0.01', '0.05'), ('0.0', '0.5'),
                                     ('nan', '0.05')])
def test_tile_heights_out_of_order_or_range_are_refused(capsys, heights):
    from biped_tools.scenarios.command import main
    with pytest.raises(SystemExit) as exit_info:
        main(['terrain', '--no-bag', '--heights', *heights])
    assert exit_info.value.code == 2
    assert '--heights' in capsys.readouterr().err


def test_the_harder_tile_set_reaches_the_trials_under_its_own_name(monkeypatch, tmp_path):
    from biped_tools.scenarios import command, terrain
    calls = []

    def run(trial, area, seed, side, stand, heights):
        calls.append((trial.setting, area, seed, heights))
        return {'success': False}
    monkeypatch.setattr(terrain, 'run', run)
    assert command.main(['terrain', '--no-bag', '--out', str(tmp_path), '--tile-areas', '100',
                         '--seeds', '2', '--heights', '0.0', '0.05', '--model', 'lipm']) == 1
    assert calls == [('100cm2_seed2_0-50mm', 100.0, 2, (0.0, 0.05))]


class _ClockOnly:
    def __init__(self, t: float) -> None:
        self.t = t

    def sim_time(self) -> float:
        return self.t


@pytest.mark.parametrize('now, start, logged', [
    (0.0, 10.0, False), (7.99, 10.0, False), (8.01, 20.0, True), (25.0, 30.0, True)])
def test_a_scripted_walk_starts_at_the_stated_time_or_the_next_multiple(now, start, logged):
    from pathlib import Path
    from biped_tools.scenarios.trial import stated_start, Trial
    lines = []
    trial = Trial('push', 'lipm', 'x', Path('/nonexistent'), 0, log=lines.append)
    assert stated_start(_ClockOnly(now), trial) == start
    assert bool(lines) == logged
