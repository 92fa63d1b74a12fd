"""The first outputs of SplitMix64 (S. Vigna's reference splitmix64.c, transcribed: the state
advances by 0x9e3779b97f4a7c15, each output is the state through the Mix13 finaliser) for the
seeds pendulab-lti's `random` tests check. Python 3 standard library only.

Run: python3 tools/reference/splitmix64.py
"""

MASK = (1 << 64) - 1
GAMMA = 0x9E3779B97F4A7C15


def mix(z):
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)


def outputs(seed, n):
    s, out = seed, []
    for _ in range(n):
        s = (s + GAMMA) & MASK
        out.append(mix(s))
    return out


if __name__ == "__main__":
    for seed in (0, 1234567):
        print(seed, ", ".join(f"{v:#018x}" for v in outputs(seed, 3)))
