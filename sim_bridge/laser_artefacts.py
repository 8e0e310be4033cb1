"""
What a real laser does to the true ranges: noise, lost returns, mixed pixels, its error codes.

The laser (`sim_bridge.laser`) casts its rays and hands the true ranges here, beam by beam in
scan order. Each artefact is one function of arrays, switched off by its parameter's neutral
value, and draws its random numbers from the laser's own ``numpy.random.Generator`` only when
it is on (so a laser with every artefact off draws nothing and gives today's exact scans):

- **range noise** (`noise_std_of`): zero-mean Gaussian, its standard deviation a floor
  ``noise_std``, growing as ``noise_fraction * range`` (data sheets state "1 % of the
  distance"), with a step to ``noise_std_far`` beyond ``far_range`` (data sheets state "+-30 mm
  to 10 m, +-50 mm beyond");
- **no return at grazing incidence** (`grazing_beams`): a beam that meets a surface at more than
  ``max_incidence`` from its normal returns nothing;
- **dropout** (`dropped_beams`): a random share ``dropout`` of the hits returns nothing,
  ``dropout_far`` beyond ``far_range``;
- **mixed pixels** (`mix_edge_pixels`): a beam beside a depth jump of more than
  ``mixed_pixel_jump`` returns, with probability ``mixed_pixel_probability``, a range between
  its own and its neighbour's, as a spot that falls on both surfaces does;
- **the driver's encoding of errors** (`encode_errors`): REP 117 (``+inf`` no return, ``-inf``
  closer than ``range_min``), NaN for both, or the old Hokuyo driver's tiny ranges (a no-echo
  beam written as its error code in millimetres, 0.000-0.019 m, below ``range_min``).

Ranges are ``(n,) ndarray of float64`` [m]; masks ``(n,) ndarray of bool``.

"""

import math

import numpy as np

#: The encodings of a beam with no valid reading: REP 117, NaN, or the old tiny-range codes.
ENCODINGS = ('rep117', 'nan', 'tiny_codes')

#: The no-echo codes of the old Hokuyo driver, as ``((range [m], weight), ...)``: the codes
#: (SCIP 2.0, URG-04LX error codes 0-19, written in millimetres) and how often each appears
#: among the readings below ``range_min`` in ``positive_1.bag`` of ``../shared/realdata``
#: (34,205 code 0, 11,362 code 6, 489 code 7, 2,983 code 8, 833 code 9, 201 code 15).
HOKUYO_ERROR_CODES = ((0.000, 34205.0), (0.006, 11362.0), (0.007, 489.0), (0.008, 2983.0),
                      (0.009, 833.0), (0.015, 201.0))


def check_artefacts(config):
    """
    Check the artefact fields of a `LaserConfig`.

    Parameters
    ----------
    config : sim_bridge.laser.LaserConfig
        Its range limits are already checked.

    Raises
    ------
    ValueError
        Naming the field out of range and what it may be.

    """
    for name in ('noise_fraction', 'noise_std_far'):
        value = getattr(config, name)
        if not (math.isfinite(value) and value >= 0.0):
            raise ValueError(f'{name} must be a non-negative finite number, got {value!r}')
    if not config.far_range > 0.0:   # inf allowed: no far band
        raise ValueError(f'far_range must be positive (inf: no far band), got '
                         f'{config.far_range!r} m')
    for name in ('dropout', 'dropout_far', 'mixed_pixel_probability'):
        value = getattr(config, name)
        if not 0.0 <= value <= 1.0:     # False for NaN
            raise ValueError(f'{name} must be a probability in [0, 1], got {value!r}')
    if not 0.0 < config.max_incidence <= 0.5 * math.pi:
        raise ValueError(f'max_incidence must be in (0, pi/2] rad (pi/2: no cut-off), got '
                         f'{config.max_incidence!r}')
    if not (math.isfinite(config.mixed_pixel_jump) and config.mixed_pixel_jump > 0.0):
        raise ValueError(f'mixed_pixel_jump must be positive, got {config.mixed_pixel_jump!r} m')
    if config.error_encoding not in ENCODINGS:
        raise ValueError(f'error_encoding must be one of {", ".join(ENCODINGS)}, got '
                         f'{config.error_encoding!r}')
    codes = config.error_codes
    try:
        values = np.asarray(codes, dtype=np.float64).reshape(-1, 2)
    except (TypeError, ValueError):
        values = np.zeros((0, 2))
    if values.shape[0] == 0 or values.shape[0] != len(codes) or \
            not np.all(np.isfinite(values)) or np.any(values[:, 1] <= 0.0):
        raise ValueError(f'error_codes must be ((range [m], weight > 0), ...), at least one, '
                         f'got {codes!r}')
    if config.error_encoding == 'tiny_codes' and not (
            np.all(values[:, 0] >= 0.0) and np.all(values[:, 0] < config.range_min)):
        raise ValueError(f'with tiny_codes every error code must lie in [0, range_min '
                         f'{config.range_min} m), or it reads as a valid range; got '
                         f'{codes!r}')


def noise_std_of(ranges, config):
    """
    Return each beam's range noise standard deviation [m].

    ``max(noise_std, noise_fraction * range)``, and at least ``noise_std_far`` beyond
    ``far_range``.

    Parameters
    ----------
    ranges : (n,) ndarray of float64
        True ranges [m].
    config : LaserConfig
        Its ``noise_std``, ``noise_fraction``, ``noise_std_far`` and ``far_range``.

    Returns
    -------
    std : (n,) ndarray of float64
        [m]

    """
    std = np.maximum(config.noise_std, config.noise_fraction * ranges)
    if config.noise_std_far > 0.0:
        std[ranges > config.far_range] = np.maximum(std[ranges > config.far_range],
                                                    config.noise_std_far)
    return std


def has_noise(config):
    """Return True when the laser adds range noise."""
    return config.noise_std > 0.0 or config.noise_fraction > 0.0 or config.noise_std_far > 0.0


def grazing_beams(directions_x, directions_y, normals, max_incidence):
    """
    Return the beams that meet their surface beyond the incidence cut-off.

    Parameters
    ----------
    directions_x, directions_y : (n,) ndarray of float64
        Unit beam directions in the map frame (the scan plane is horizontal).
    normals : (n, 3) ndarray of float64
        Surface normals at the hits, as ``rayTestBatch`` returns them (zero for a miss).
    max_incidence : float
        Largest angle between a beam and the surface normal that still returns [rad].

    Returns
    -------
    grazing : (n,) ndarray of bool
        True where ``|cos(incidence)| < cos(max_incidence)`` (also for a miss's zero normal).

    """
    cos_incidence = np.abs(directions_x * normals[:, 0] + directions_y * normals[:, 1])
    return cos_incidence < math.cos(max_incidence)


def dropped_beams(ranges, hit, config, rng):
    """
    Draw the hits that return nothing at random.

    Parameters
    ----------
    ranges : (n,) ndarray of float64
        Ranges [m].
    hit : (n,) ndarray of bool
        Beams with a return.
    config : LaserConfig
        ``dropout`` within ``far_range``, ``max(dropout, dropout_far)`` beyond.
    rng : numpy.random.Generator
        Draws ``n`` uniforms.

    Returns
    -------
    dropped : (n,) ndarray of bool

    """
    probability = np.where(ranges > config.far_range, max(config.dropout, config.dropout_far),
                           config.dropout)
    return hit & (rng.random(ranges.shape[0]) < probability)


def has_dropout(config):
    """Return True when hits may drop out."""
    return config.dropout > 0.0 or config.dropout_far > 0.0


def mix_edge_pixels(ranges, hit, probability, jump, rng, wraps=False):
    """
    Give beams beside a depth jump a range between the two surfaces, at random.

    A hit beam whose hit neighbour (the previous or next beam) is more than ``jump`` nearer or
    farther is an edge beam. With ``probability`` it returns ``r + u * (r_n - r)``, ``u``
    uniform in [0, 1), ``r_n`` the range of the neighbour across the larger jump.

    Parameters
    ----------
    ranges : (n,) ndarray of float64
        True ranges [m]; not changed.
    hit : (n,) ndarray of bool
        Beams with a return.
    probability : float
        Chance that an edge beam is mixed.
    jump : float
        Smallest depth difference that makes an edge [m].
    rng : numpy.random.Generator
        Draws ``2 n`` uniforms.
    wraps : bool
        The first and last beams are neighbours (a full-turn scan).

    Returns
    -------
    mixed_ranges : (n,) ndarray of float64
        A new array.
    mixed : (n,) ndarray of bool
        The beams given a mixed range.

    """
    n = ranges.shape[0]
    chance = rng.random(n)
    share = rng.random(n)
    best = np.zeros(n)
    partner = ranges.copy()
    for shift in (1, -1):
        other = np.roll(ranges, shift)
        other_hit = np.roll(hit, shift)
        if not wraps:
            other_hit[0 if shift == 1 else -1] = False
        difference = np.where(hit & other_hit, np.abs(other - ranges), 0.0)
        larger = difference > best
        best[larger] = difference[larger]
        partner[larger] = other[larger]
    mixed = (best > jump) & (chance < probability)
    out = ranges.copy()
    out[mixed] += share[mixed] * (partner[mixed] - ranges[mixed])
    return out, mixed


def encode_errors(ranges, no_return, too_close, config, rng):
    """
    Write the beams with no valid reading as the driver does.

    Parameters
    ----------
    ranges : (n,) ndarray of float64
        Ranges [m]; changed in place.
    no_return, too_close : (n,) ndarray of bool
        Beams that returned nothing, and hits closer than ``range_min``.
    config : LaserConfig
        ``error_encoding``: ``'rep117'`` (``+inf`` and ``-inf``), ``'nan'`` (NaN for both) or
        ``'tiny_codes'`` (a code of ``error_codes``, drawn by weight, for both).
    rng : numpy.random.Generator
        Draws one code per invalid beam with ``'tiny_codes'``; nothing otherwise.

    Returns
    -------
    ranges : (n,) ndarray of float64
        The same array.

    """
    if config.error_encoding == 'rep117':
        ranges[no_return] = math.inf
        ranges[too_close] = -math.inf
    elif config.error_encoding == 'nan':
        ranges[no_return | too_close] = math.nan
    else:
        invalid = no_return | too_close
        codes = np.asarray(config.error_codes, dtype=np.float64).reshape(-1, 2)
        weights = codes[:, 1] / codes[:, 1].sum()
        ranges[invalid] = rng.choice(codes[:, 0], size=int(np.count_nonzero(invalid)),
                                     p=weights)
    return ranges
