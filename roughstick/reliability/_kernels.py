"""Plain-numpy kernels of subset simulation (:func:`roughstick.reliability.subset_simulation`).

Subset simulation (Au & Beck 2001) in the standard-normal space of the white noise that
roughstick's generator filters by the PSD, with preconditioned Crank-Nicolson (pCN) moves

    z' = rho z + sqrt(1 - rho^2) xi,     xi ~ N(0, I),

which leave N(0, I) invariant, so a chain conditioned on {Y(z) > b} needs no Metropolis ratio
but the indicator: accept z' iff Y(z') > b (Cotter, Roberts, Stuart & White 2013; Papaioannou,
Betz, Zwirglmaier & Straub 2015 for its use in subset simulation).

Reproducibility: every random draw comes from one generator per (run, level, chain) or per
level-0 sample (:func:`step_rng`, :func:`sample_rng`), each drawing a fixed number of normals per
step whatever happens, so a chain is replayed exactly from its seed state and its acceptance flags
(:func:`replay_chain`) and the result does not depend on how chains are grouped into tasks.
"""

from __future__ import annotations

import math

import numpy as np

__all__: list[str] = []

#: spawn-key tag of the chains of levels >= 1: (run, level, chain) keys have 4 entries, the
#: level-0 keys (realization index,) one, so they can never collide.
_CHAIN_TAG = 0x5355  # "SU"


def sample_rng(entropy, spawn_key, index: int) -> np.random.Generator:
    """Generator of level-0 sample ``index``: one SeedSequence child per sample index."""
    ss = np.random.SeedSequence(entropy, spawn_key=tuple(spawn_key) + (int(index),))
    return np.random.default_rng(ss)


def step_rng(entropy, spawn_key, run: int, level: int, chain: int, step: int) -> np.random.Generator:
    """Generator of the proposal of ``step`` of ``chain`` at ``level`` (>= 1) of run ``run``.

    One SeedSequence child per (run, level, chain, step): a chain's proposals do not depend on
    the order in which chains or steps are evaluated, and any state is replayed from the seed and
    the acceptance flags alone.
    """
    key = tuple(spawn_key) + (_CHAIN_TAG, int(run), int(level), int(chain), int(step))
    return np.random.default_rng(np.random.SeedSequence(entropy, spawn_key=key))


def proposal_scales(spread: np.ndarray, scale: float):
    """Per-coordinate pCN parameters: ``sigma = min(1, scale * spread)``, ``rho = sqrt(1 - sigma^2)``.

    ``spread`` is the standard deviation of the level's seeds in each white-noise coordinate
    (adaptive conditional sampling, Papaioannou et al. 2015): coordinates the failure region
    constrains get smaller steps. Each coordinate's move ``rho z + sigma xi`` leaves N(0, 1)
    invariant, so the prior, hence the PSD, is kept exactly.
    """
    sigma = np.minimum(1.0, scale * spread)
    return np.sqrt(1.0 - sigma * sigma), sigma


def pcn_move(z: np.ndarray, xi: np.ndarray, rho, sigma) -> np.ndarray:
    """The pCN proposal ``rho z + sigma xi`` (one expression, used by the chains and the replay)."""
    return rho * z + sigma * xi


def evaluate_samples(model, indices, *, entropy, spawn_key, noise_shape):
    """Level 0: responses of the independent samples ``indices`` (float array)."""
    out = np.empty(len(indices))
    for k, i in enumerate(indices):
        z = sample_rng(entropy, spawn_key, i).standard_normal(noise_shape)
        out[k] = model(z)
    return out


def sample_noise(index, *, entropy, spawn_key, noise_shape):
    """The white noise of level-0 sample ``index`` (regenerated from its seed)."""
    return sample_rng(entropy, spawn_key, index).standard_normal(noise_shape)


def chain_step(model, z, y, *, threshold, move, rng):
    """One conditional move: ``(z_new, y_new, proposal_response, accepted)``.

    ``move(z, rng)`` is a proposal reversible for the N(0, I) prior (``_moves``), so the
    proposal is accepted iff its response is strictly above ``threshold`` (NaN: rejected).
    """
    cand = move(z, rng)
    yc = float(model(cand))
    if yc > threshold:
        return cand, yc, yc, 1
    return z, y, yc, 0


def replay_chain(z0, accepted, steps, *, moves, rng_of_step):
    """States of a chain at ``steps`` from its seed and acceptance flags (no model evaluation).

    ``moves[k]`` is the move of step ``k`` and ``rng_of_step(k)`` its generator: the same normals
    combined by the same move, so the states are bit-identical to those the chain visited.
    """
    want = sorted(set(int(s) for s in steps))
    out = {}
    z = np.array(z0, dtype=float, copy=True)
    last = want[-1] if want else 0
    for k in range(0, last + 1):
        if k > 0 and accepted[k]:
            z = moves[k](z, rng_of_step(k))
        if k in want:
            out[k] = z.copy()
    return [out[int(s)] for s in steps]


def chain_lengths(n_samples: int, n_chains: int) -> np.ndarray:
    """Split ``n_samples`` states over ``n_chains`` chains as evenly as possible (first longer)."""
    base, extra = divmod(int(n_samples), int(n_chains))
    return np.array([base + (1 if c < extra else 0) for c in range(n_chains)], dtype=np.int64)


def intermediate_threshold(response: np.ndarray, n_keep: int) -> float:
    """Au & Beck's threshold: midway between the ``n_keep``-th and ``n_keep+1``-th largest.

    NaN responses count as -inf (never above any threshold).
    """
    y = np.where(np.isnan(response), -np.inf, response)
    top = np.sort(y)[::-1]
    a, b = top[n_keep - 1], top[n_keep]
    if not np.isfinite(b):
        return float(a) if np.isfinite(a) else -np.inf
    return float(0.5 * (a + b))


def correlation_factor(indicator_chains, p: float) -> float:
    r"""Au & Beck's :math:`\gamma` of one level from the failure indicators of its chains.

    .. math:: \gamma = 2\sum_{k=1}^{L-1}\Big(1 - \frac{k}{L}\Big)\frac{R(k)}{R(0)},\quad
              R(k) = \overline{I_{c,l} I_{c,l+k}} - p^2,\quad R(0) = p(1 - p),

    the average over all pairs at lag :math:`k` inside a chain, :math:`L` the mean chain
    length (chains of unequal length are allowed). 0 when :math:`p \in \{0, 1\}`. The states of
    a Metropolis chain are positively correlated, so a negative estimate is sampling noise of
    short chains: it is clipped at 0 (the binomial variance), never below, which would make the
    level's variance (1 - p)/(n p) (1 + gamma) negative.
    """
    if not 0.0 < p < 1.0:
        return 0.0
    chains = [np.asarray(c, dtype=float) for c in indicator_chains if len(c) > 0]
    n = sum(c.size for c in chains)
    L = n / len(chains)
    kmax = max(c.size for c in chains) - 1
    r0 = p * (1.0 - p)
    gamma = 0.0
    for k in range(1, kmax + 1):
        num = 0.0
        pairs = 0
        for c in chains:
            if c.size > k:
                num += float(np.dot(c[:-k], c[k:]))
                pairs += c.size - k
        if pairs == 0 or k >= L:
            break
        gamma += 2.0 * (1.0 - k / L) * ((num / pairs - p * p) / r0)
    return max(float(gamma), 0.0)


def level_cv2(p: float, n: int, gamma: float) -> float:
    """Squared cv of one level's conditional probability, (1-p)/(n p) (1 + gamma); inf if p = 0."""
    if p <= 0.0:
        return math.inf
    return (1.0 - p) / (n * p) * (1.0 + gamma)


def lognormal_interval(p: float, cv: float, confidence: float, quantile: float | None = None):
    """Interval ``p sqrt(1 + cv^2) exp(+-z s)``, ``s^2 = log(1 + cv^2)``: log-normal estimator.

    Inverts a log-normal sampling distribution of the estimate with mean the true p and
    coefficient of variation ``cv``.

    The subset-simulation estimator is a product of level fractions, nearly log-normal; this
    interval stays positive and is asymmetric like its sampling distribution.
    """
    from scipy.special import ndtri

    if not (p > 0.0 and np.isfinite(cv)):
        return (np.nan, np.nan)
    z = float(ndtri(0.5 + confidence / 2.0)) if quantile is None else float(quantile)
    s = math.sqrt(math.log1p(cv * cv))
    # log P_hat = log p - s^2/2 + s eps (mean p): invert for p
    centre = p * math.sqrt(1.0 + cv * cv)
    w = min(z * s, 700.0)  # a quantile of Student's t with a fraction of a degree of freedom
    return (centre * math.exp(-w), centre * math.exp(w))


def wilson_interval(k: int, n: int, confidence: float):
    """Wilson score interval of a binomial proportion k / n."""
    from scipy.special import ndtri

    if n <= 0:
        return (np.nan, np.nan)
    z = float(ndtri(0.5 + confidence / 2.0))
    denom = n + z * z
    centre = (k + z * z / 2.0) / denom
    half = z / denom * math.sqrt(k * (n - k) / n + z * z / 4.0)
    lo = 0.0 if k == 0 else max(centre - half, 0.0)
    hi = 1.0 if k == n else min(centre + half, 1.0)
    return (lo, hi)


def adapt_scale(scale: float, acceptance: float, target: float, update: int) -> float:
    """Robbins-Monro update of the proposal scale after the ``update``-th round of a level.

    ``log scale += (acceptance - target) / sqrt(update)`` (Papaioannou et al. 2015, Algorithm 5):
    larger steps when too many proposals are accepted, smaller when too few. Applied between
    rounds (one step of every chain of the level), so all chains of a round share one kernel and
    the result does not depend on how chains are grouped into tasks.
    """
    if not np.isfinite(acceptance):
        return scale
    return float(math.exp(math.log(scale) + (acceptance - target) / math.sqrt(update)))


# --------------------------------------------------------------------------------------------


def root_ancestors(levels_chain, levels_kept):
    """Level-0 ancestor ("Eve") of every state of every level of one subset-simulation run.

    ``levels_chain[j]`` is the chain (= seed index) of each state of level ``j >= 1`` (ignored at
    level 0) and ``levels_kept[j]`` the sorted sample indices level ``j`` kept as the seeds of
    level ``j + 1``: seed ``c`` of level ``j + 1`` is state ``levels_kept[j][c]`` of level ``j``.
    Returns one integer array per level; level 0's states are their own roots.
    """
    roots = []
    for j, chain in enumerate(levels_chain):
        if j == 0:
            roots.append(np.arange(np.asarray(chain).size, dtype=np.int64))
        else:
            seed_root = roots[j - 1][np.asarray(levels_kept[j - 1], dtype=np.int64)]
            roots.append(seed_root[np.asarray(chain, dtype=np.int64)])
    return roots


def genealogical_cv2(final_roots, final_indicator, n_roots: int) -> float:
    r"""Squared cv of a run's estimate from its genealogy (clusters by level-0 ancestor).

    The estimate :math:`\hat P = p_0^{m-1} n_F / N` is a sum of the contributions of the
    :math:`N` level-0 samples, :math:`c_i \propto n_i`, the final failures descending from
    sample :math:`i`. Treating these clusters as exchangeable,

    .. math:: \hat\delta^2 = \frac{N}{N-1}\sum_{i=1}^{N}\Big(\frac{n_i}{n_F} - \frac1N\Big)^2,

    the ancestral-lineage variance estimator of sequential Monte Carlo (Chan & Lai 2013; Lee &
    Whiteley 2018) applied to subset simulation. Unlike Au & Beck's level formula it contains the
    correlation of the states of a chain *and* of the levels (descendants of one ancestor
    succeed or fail together), which is what that formula misses. With one level it is the
    binomial :math:`(1-\hat p)/(N\hat p)` (up to :math:`N/(N-1)`). ``inf`` if no failure.
    """
    ind = np.asarray(final_indicator, dtype=bool)
    n_f = int(ind.sum())
    if n_f == 0:
        return math.inf
    # sum_i (n_i/n_F - 1/N)^2 = sum_i (n_i/n_F)^2 - 1/N over the ancestors with failures only (root
    # indices may exceed N when some level-0 samples are NaN, which are no ancestors)
    counts = np.unique(np.asarray(final_roots, dtype=np.int64)[ind], return_counts=True)[1]
    frac = counts / n_f
    return max(float(n_roots / (n_roots - 1) * (np.dot(frac, frac) - 1.0 / n_roots)), 0.0)  # rounding


def effective_lineages(final_roots, final_indicator) -> float:
    r"""Effective number of independent final lineages of a run, :math:`1/\sum_i (n_i/n_F)^2`.

    :math:`n_i` is the number of final failures descending from level-0 sample :math:`i`
    (Kish's effective sample size of the clusters by ancestor). The genealogical squared cv is
    :math:`\frac{N}{N-1}(1/N_{\rm eff} - 1/N)`: it cannot exceed 1, and it rests on about
    :math:`N_{\rm eff}` independent contributions. 0 if no failure.

    >>> effective_lineages([3, 3, 3, 5], [True, True, True, True])  # 3 + 1 failures
    1.6
    """
    ind = np.asarray(final_indicator, dtype=bool)
    if not ind.any():
        return 0.0
    counts = np.unique(np.asarray(final_roots, dtype=np.int64)[ind], return_counts=True)[1]
    frac = counts / counts.sum()
    return float(1.0 / np.dot(frac, frac))


def lineage_cv2(cv2: float, lineages: float) -> float:
    r"""The genealogical squared cv with Bessel's correction on the effective lineages.

    The genealogical variance is a sample variance of the level-0 ancestors' contributions, of
    which only about :math:`N_{\rm eff}` (:func:`effective_lineages`) are independent and non-zero:
    it is corrected as a variance from :math:`N_{\rm eff}` values, :math:`\delta^2 N_{\rm eff} /
    (N_{\rm eff} - 1)`. Negligible with many lineages, it grows without bound as they collapse to
    one, where the genealogy says nothing about the variance (``inf``): the uncorrected
    estimator cannot exceed 1 and is optimistic exactly there.

    >>> round(lineage_cv2(0.25, 5.0), 4)
    0.3125
    >>> lineage_cv2(1.0, 1.0)
    inf
    """
    if not lineages > 1.0 + 1e-9:
        return math.inf
    return float(cv2 * lineages / (lineages - 1.0))
