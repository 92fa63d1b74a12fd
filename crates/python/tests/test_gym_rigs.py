"""The rig environments: Gymnasium's env checker, the native vector env against
``SyncVectorEnv`` over the single environments, one step against SciPy's integration of the
model equations written out from docs/model.md, and bad inputs."""

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from scipy.integrate import solve_ivp

import pendulab
import pendulab.gym  # noqa: F401
from pendulab.gym import CartPoleEnv, RigEnv, RigVectorEnv

IDS = ["pendulab/CartRig-v0", "pendulab/CartRigSwingUp-v0", "pendulab/ArmRig-v0", "pendulab/ArmRigSwingUp-v0"]


@pytest.mark.parametrize("env_id", ["pendulab/CartPole-v1", *IDS])
def test_check_env_passes(env_id):
    check_env(gymnasium.make(env_id).unwrapped, skip_render_check=True)


def test_check_env_passes_with_quantized_observations():
    env = RigEnv("cart", quantize=True)
    check_env(env, skip_render_check=True)
    obs, _ = env.reset(seed=3)
    # Observed positions are whole encoder counts; velocities are the state's.
    q = (4.8414e-5, 2 * np.pi / 14400)
    for i in (0, 1):
        assert abs(obs[i] / q[i] - round(obs[i] / q[i])) < 1e-6
        assert abs(obs[i] - env.state[i]) <= q[i] / 2 * (1 + 1e-12)
    np.testing.assert_array_equal(obs[2:], env.state[2:])


@pytest.mark.parametrize(
    "rig,task,quantize",
    [("cart", "balance", False), ("cart", "swingup", True), ("arm", "balance", True), ("arm", "swingup", False)],
)
@pytest.mark.parametrize("num_envs,threads", [(5, 1), (700, 2)])
def test_vector_env_equals_single_envs_step_for_step(rig, task, quantize, num_envs, threads):
    kw = dict(rig=rig, task=task, quantize=quantize, max_steps=60)
    ours = RigVectorEnv(num_envs=num_envs, threads=threads, **kw)
    ref = gymnasium.vector.SyncVectorEnv([lambda: RigEnv(**kw) for _ in range(num_envs)])
    o1, _ = ours.reset(seed=9)
    o2, _ = ref.reset(seed=9)
    np.testing.assert_array_equal(o1, o2)
    rng = np.random.default_rng(1)
    ended = 0
    for _ in range(130):
        a = rng.uniform(-6, 6, size=(num_envs, 1)).astype(np.float32)
        o1, r1, te1, tr1, _ = ours.step(a)
        o2, r2, te2, tr2, _ = ref.step(a)
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(r1, r2)
        np.testing.assert_array_equal(te1, te2)
        np.testing.assert_array_equal(tr1, tr2)
        ended += int(te1.sum() + tr1.sum())
    # 130 steps of at most 60: every environment has ended at least twice.
    assert ended >= 2 * num_envs


def cart_rhs(t, x, v):
    """docs/model.md §1 with table 3.5."""
    a_c, b_c, m, l, Jp, mu, g = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81
    J = Jp + m * l * l
    ddz = -a_c * x[2] + b_c * v
    return [x[2], x[3], ddz, (m * g * l * np.sin(x[1]) - mu * x[3] - m * l * np.cos(x[1]) * ddz) / J]


def test_cart_step_is_the_model_integrated_over_dt():
    env = RigEnv("cart", substeps=20)
    rng = np.random.default_rng(2)
    for k in range(20):
        env.reset(seed=k)
        x0 = env.state.copy()
        v = float(rng.uniform(-5, 5))
        obs, reward, *_ = env.step(np.array([v], dtype=np.float32))
        ref = solve_ivp(cart_rhs, (0, 0.02), x0, args=(float(np.float32(v)),), rtol=1e-12, atol=1e-14, method="DOP853").y[:, -1]
        # RK4 with h = 1 ms: local error ~ (|λ| h)⁵/120 · X per step with |λ| ≤ 6.3 1/s and
        # X ≲ |θ̈|/|λ| ≈ 75/6.3 ≈ 12 (the input's scale at 5 V): 20 steps ≈ 2e-11 ≪ 1e-9.
        np.testing.assert_allclose(obs, ref, atol=1e-9)
        assert reward == 1.0


def test_swingup_reward_and_clipping():
    env = RigEnv("cart", task="swingup")
    obs, _ = env.reset(seed=0)
    assert abs(obs[1] - np.pi) <= 0.05
    _, r, *_ = env.step(np.array([0.0], dtype=np.float32))
    assert r == pytest.approx(0.5 * (1 + np.cos(env.state[1])), rel=1e-15)
    # ±5 V: a larger voltage is clipped.
    a, b = RigEnv("cart"), RigEnv("cart")
    a.reset(seed=1), b.reset(seed=1)
    np.testing.assert_array_equal(a.step(np.array([50.0]))[0], b.step(np.array([5.0]))[0])


def test_bad_inputs_raise():
    with pytest.raises(pendulab.InvalidArgumentError, match="task"):
        RigEnv("cart", task="juggle")
    with pytest.raises(pendulab.InvalidArgumentError, match="rig"):
        RigEnv("boat")
    with pytest.raises(pendulab.InvalidArgumentError, match="m_p"):
        RigEnv("cart", params={"m_p": 0.0})
    with pytest.raises(ValueError, match="dt"):
        RigEnv("cart", dt=-1.0)
    env = RigEnv("arm")
    env.reset(seed=0)
    with pytest.raises(pendulab.NotFiniteError):
        env.step(np.array([np.nan]))
    with pytest.raises(pendulab.ShapeError):
        env.step(np.array([1.0, 2.0]))
    envs = RigVectorEnv(num_envs=3)
    envs.reset(seed=0)
    with pytest.raises(pendulab.ShapeError, match="expected 3 actions"):
        envs.step(np.zeros(2))
    with pytest.raises(pendulab.ShapeError):
        envs._core.reset([1, 2])
