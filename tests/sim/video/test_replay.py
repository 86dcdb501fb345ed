import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.video.replay import Snapshot, apply_snapshot, replay_scene, take_snapshot


def test_replay_scene_takes_the_recorded_poses_and_joints():
    with PhysicalWorld(3) as world:
        world.build(parse_config("AB+C"))  # C held by a real grasp: arm and fingers away from home
        snap = take_snapshot(world.scene)
    assert isinstance(snap, Snapshot) and len(snap.poses) == 3 and len(snap.joints) == 11
    with replay_scene(3) as scene:
        assert scene.replay_only
        apply_snapshot(scene, snap.poses, snap.joints)
        again = take_snapshot(scene)
    for a, b in zip(again.poses, snap.poses, strict=True):
        assert a.position == pytest.approx(b.position, abs=1e-9)
    assert again.joints == pytest.approx(snap.joints, abs=1e-9)


def test_a_physics_scene_is_never_posed_from_a_snapshot():
    with PhysicalWorld(3) as world:
        world.build(parse_config("A,B,C"))
        snap = take_snapshot(world.scene)
        with pytest.raises(RuntimeError):
            apply_snapshot(world.scene, snap.poses, snap.joints)
