"""
Intervals and tests for benchmark results: map-stratified bootstrap and the exact sign test.

Episodes of one map share its corridors, so they are not independent draws across maps; the
bootstrap here resamples episodes **within each map** (stratified by map, every map keeping its
episode count), which is the design the protocol has (every map run equally often). The
percentile interval of the resampled statistic is reported. The exact sign test works in
integers and fractions, so it holds for any number of episodes.

"""

from fractions import Fraction
import math

import numpy as np

#: Bootstrap resamples; the 2.5 % and 97.5 % percentiles of 2,000 move by about 0.1 of a
#: standard error between seeds.
BOOTSTRAP_RESAMPLES = 2000
#: Seed of the bootstrap's generator: the same log gives the same interval.
BOOTSTRAP_SEED = 0


def sign_test(won, lost):
    """
    Return the exact two-sided sign-test p-value of ``won`` against ``lost`` (McNemar's exact).

    Of the episodes that two navigators end differently, each is as likely to go either way
    when the navigators are equally good; the p-value is the probability of a split at least
    this uneven under that hypothesis: ``min(1, 2 * sum_{k <= min} C(n, k) / 2**n)``, in exact
    integers (no overflow for any ``n``; a p-value below the smallest float reads 0.0). 1.0
    when no episode differs.

    Raises
    ------
    ValueError
        For a negative or non-integer count.

    """
    for value in (won, lost):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
            raise ValueError(f'counts must be non-negative integers, got {value!r}')
    total = int(won) + int(lost)
    if total == 0:
        return 1.0
    tail = sum(math.comb(total, k) for k in range(min(int(won), int(lost)) + 1))
    return float(min(Fraction(1), Fraction(2 * tail, 2 ** total)))


def stratified_bootstrap(values, strata, statistic=np.mean, resamples=BOOTSTRAP_RESAMPLES,
                         seed=BOOTSTRAP_SEED, level=0.95):
    """
    Return a percentile bootstrap interval of a statistic, resampling within each stratum.

    Parameters
    ----------
    values : (N,) or (N, K) array_like of float
        One value (or row of values) per episode; nan values are left out first.
    strata : (N,) sequence
        Each episode's stratum (its map).
    statistic : callable
        Of an (n,) or (n, K) array, returning a float (``numpy.mean`` by default).
    resamples : int
        Bootstrap resamples.
    seed : int
        The generator's seed.
    level : float
        Coverage in (0, 1).

    Returns
    -------
    estimate, low, high : float
        The statistic on the data and the interval's bounds; nan when there are no values.

    """
    values = np.asarray(values, dtype=np.float64)
    strata = np.asarray(strata)
    if values.shape[0] != strata.shape[0]:
        raise ValueError(f'{values.shape[0]} values but {strata.shape[0]} strata')
    if not 0.0 < level < 1.0:
        raise ValueError(f'level must lie in (0, 1), got {level!r}')
    keep = ~np.isnan(values) if values.ndim == 1 else ~np.isnan(values).any(axis=1)
    values, strata = values[keep], strata[keep]
    if values.shape[0] == 0:
        return math.nan, math.nan, math.nan
    estimate = float(statistic(values))
    rng = np.random.default_rng(seed)
    groups = [np.flatnonzero(strata == stratum) for stratum in np.unique(strata)]
    draws = np.empty(resamples)
    for i in range(resamples):
        index = np.concatenate([group[rng.integers(0, group.shape[0], group.shape[0])]
                                for group in groups])
        draws[i] = statistic(values[index])
    tail = 100.0 * (1.0 - level) / 2.0
    low, high = np.percentile(draws, [tail, 100.0 - tail])
    return estimate, float(low), float(high)


def paired_difference(subject, other, strata, **options):
    """
    Return the mean of ``subject - other`` over paired episodes with its bootstrap interval.

    Parameters
    ----------
    subject, other : (N,) array_like of float
        The same episodes' values for two navigators (e.g. success as 0/1).
    strata : (N,) sequence
        Each episode's map.
    **options
        Passed to `stratified_bootstrap`.

    Returns
    -------
    estimate, low, high : float

    """
    difference = np.asarray(subject, dtype=np.float64) - np.asarray(other, dtype=np.float64)
    return stratified_bootstrap(difference, strata, **options)


def format_interval(estimate, low, high, scale=1.0, digits=1):
    """Return ``'e [l, h]'`` with the values times ``scale``, or ``'-'`` for nan."""
    if math.isnan(estimate):
        return '-'
    return (f'{scale * estimate:.{digits}f} [{scale * low:.{digits}f}, '
            f'{scale * high:.{digits}f}]')
