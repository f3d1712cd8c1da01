"""Expanding a campaign into jobs and drawing each sample's conditions on a real world."""

import textwrap

import numpy as np
import pytest

from robocop_dsl.campaign import draw_conditions, read_campaign
from robocop_dsl.campaign.checker import Pairing
from robocop_dsl.campaign.jobs import expand

CAMPAIGN = """
    missions: [pickup.mission]
    samples: 40
    seed: 11
    settings: {solver: [proxqp, quadprog], hierarchy: [strict, weighted]}
    vary:
      bodies:
        - move: [pickup_point, part_body]
          uniform: {low: [0.6, 0.1, 0.76], high: [0.8, 0.3, 0.8]}
        - move: drop_point
          normal: {std: [0.01, 0.01, 0]}
      initial_posture:
        - joints: bazar_left_arm
          normal: {std: 2.0}
        - joints: bazar_ptu
          uniform: {low: -0.1, high: 0.1}
    """


@pytest.fixture()
def jobs(tmp_path):
    path = tmp_path / "sampled.campaign.yaml"
    path.write_text(textwrap.dedent(CAMPAIGN), encoding="utf-8")
    spec = read_campaign(path)
    pairings = [Pairing("/m/pickup.mission", "pickup", variant, "/w/sophia.yaml",
                        spec.missions[0]) for variant in ("a", "b")]
    return expand(spec, pairings)


def same(first, second):
    return (first.parameters == second.parameters
            and np.array_equal(first.initial, second.initial)
            and all(np.array_equal(first.body_placements[b], second.body_placements[b])
                    for b in first.body_placements))


def test_expansion_order_and_count(jobs):
    """Jobs run over variants, then settings combinations, then samples, numbered in order."""
    assert len(jobs) == 2 * 4 * 40
    assert [job.index for job in jobs] == list(range(len(jobs)))
    assert [(j.variant, j.settings, j.sample) for j in jobs[39:41]] == [
        ("a", (("solver", "proxqp"), ("hierarchy", "strict")), 39),
        ("a", (("solver", "proxqp"), ("hierarchy", "weighted")), 0)]
    assert jobs[-1].variant == "b" and jobs[-1].setting("solver") == "quadprog"
    assert all(job.bodies[0].where is None for job in jobs)


def test_a_sample_is_the_same_on_every_variant_and_setting(bazar, jobs):
    """Sample k's conditions depend on the seed and k only, whatever the job."""
    by_sample = {}
    for job in jobs[::7]:
        conditions = draw_conditions(job, bazar)
        if job.sample in by_sample:
            assert same(by_sample[job.sample], conditions)
        by_sample[job.sample] = conditions
    assert not same(draw_conditions(jobs[0], bazar), draw_conditions(jobs[1], bazar))


def test_draws_do_not_depend_on_order(bazar, jobs):
    """Drawing the jobs backwards gives each job the same conditions."""
    forwards = [draw_conditions(job, bazar) for job in jobs[:40]]
    backwards = [draw_conditions(job, bazar) for job in reversed(jobs[:40])][::-1]
    assert all(same(a, b) for a, b in zip(forwards, backwards))


def test_moved_bodies_stay_together_in_the_box(bazar, jobs):
    """Bodies moved together keep their offsets and orientations; positions stay in the box."""
    start = bazar.initial_configuration()
    nominal = {b: bazar.body_pose(b, start).homogeneous
               for b in ("pickup_point", "part_body", "drop_point")}
    offset = nominal["part_body"][:3, 3] - nominal["pickup_point"][:3, 3]
    for job in jobs[:40]:
        placements = draw_conditions(job, bazar).body_placements
        pickup, part = placements["pickup_point"], placements["part_body"]
        assert np.all(pickup[:3, 3] >= [0.6, 0.1, 0.76])
        assert np.all(pickup[:3, 3] <= [0.8, 0.3, 0.8])
        np.testing.assert_allclose(part[:3, 3] - pickup[:3, 3], offset, atol=1e-12)
        for body, pose in placements.items():
            np.testing.assert_array_equal(pose[:3, :3], nominal[body][:3, :3])
        assert placements["drop_point"][2, 3] == nominal["drop_point"][2, 3]


def test_normal_without_mean_is_centred_on_the_body(bazar, jobs):
    """The drop point scatters around where the world puts it."""
    start = bazar.initial_configuration()
    nominal = bazar.body_pose("drop_point", start).translation
    drawn = np.array([draw_conditions(job, bazar).body_placements["drop_point"][:3, 3]
                      for job in jobs[:40]])
    assert np.all(np.abs(drawn.mean(axis=0) - nominal) < 4 * 0.01 / np.sqrt(40))
    assert 0.005 < drawn[:, 0].std() < 0.02


def test_posture_noise_is_clipped_and_confined(bazar, jobs):
    """Noise moves only the named joints, around the initial posture, within the limits."""
    start = bazar.initial_configuration()
    left = bazar.joint_group("bazar_left_arm")
    ptu = bazar.joint_group("bazar_ptu")
    moved = np.concatenate([left.q_indices, ptu.q_indices])
    others = np.setdiff1d(np.arange(len(start)), moved)
    clipped = 0
    for job in jobs[:40]:
        conditions = draw_conditions(job, bazar)
        q = conditions.initial
        np.testing.assert_array_equal(q[others], start[others])
        assert np.all(q[left.q_indices] >= left.lower) and np.all(q[left.q_indices] <= left.upper)
        assert np.all(np.abs(q[ptu.q_indices] - start[ptu.q_indices]) <= 0.1)
        clipped += np.sum((q[left.q_indices] == left.lower) | (q[left.q_indices] == left.upper))
        assert conditions.parameters[f"initial.{left.joints[3]}"] == q[left.q_indices[3]]
    assert clipped > 0
