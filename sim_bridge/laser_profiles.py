"""
Named lasers modelled on published data sheets: beam layout, range limits, rate and artefacts.

``ideal`` is the paper's perfect laser (the `LaserConfig` defaults). The others take their
field of view, angular step, range limits, rate and range noise from the maker's documents,
cited in ``docs/simulator.md``; the rates of their other artefacts (dropout, the grazing cut-off,
mixed pixels) are not on any data sheet and are assumptions, said so there. Every profile keeps
the Husky's mount (`sim_bridge.husky.LASER_MOUNT`), so only the sensor changes.

A data sheet's "accuracy +-a" is read as a two-sigma bound: the noise's standard deviation is
``a / 2`` (an assumption; SICK alone gives a one-sigma "statistical error").

"""

from dataclasses import dataclass, fields, replace
import math

from .laser import LaserConfig
from .named_profiles import named_profile


@dataclass(frozen=True)
class LaserProfile:
    """
    A named laser.

    Attributes
    ----------
    name : str
        The profile's name (``--laser``, the ``laser_profile`` parameter).
    laser : LaserConfig
        Beam layout, range limits and artefacts.
    scan_rate : float
        The sensor's scan rate on its data sheet [Hz], at this angular step. The world takes
        scans at ``WorldConfig.scan_rate``; the benchmark keeps its 10 Hz for every profile.
    sensor : str
        The sensor it models.

    """

    name: str
    laser: LaserConfig
    scan_rate: float
    sensor: str


def _layout(first_step, last_step, steps_per_turn):
    """Return ``angle_min``, ``angle_max``, ``n_beams`` of beams ``first..last`` [rad]."""
    increment = 2.0 * math.pi / steps_per_turn
    return {'angle_min': first_step * increment, 'angle_max': last_step * increment,
            'n_beams': last_step - first_step + 1}


#: The profiles, by name (``--laser`` choices).
LASER_PROFILES = {profile.name: profile for profile in (
    LaserProfile('ideal', LaserConfig(), 10.0, "the paper's perfect 640-beam, 180 deg laser"),
    # SICK LMS111/LMS151 at 50 Hz: 270 deg in 0.5 deg steps, 0.5-20 m; statistical error
    # 12 mm (1 sigma); 18 m reach at 10 % remission.
    LaserProfile('sick_lms1xx', LaserConfig(
        **_layout(-270, 270, 720), range_min=0.5, range_max=20.0, noise_std=0.012,
        far_range=18.0, dropout=0.002, dropout_far=0.05, max_incidence=math.radians(80.0),
        mixed_pixel_probability=0.2), 50.0, 'SICK LMS111 / LMS151'),
    # Hokuyo UTM-30LX: steps 0..1080 of 1440 per turn (0.25 deg, 270 deg), 0.1-30 m, 40 Hz;
    # +-30 mm to 10 m, +-50 mm to 30 m.
    LaserProfile('hokuyo_utm30lx', LaserConfig(
        **_layout(-540, 540, 1440), range_min=0.1, range_max=30.0, noise_std=0.015,
        noise_std_far=0.025, far_range=10.0, dropout=0.005, dropout_far=0.02,
        max_incidence=math.radians(75.0), mixed_pixel_probability=0.2), 40.0,
        'Hokuyo UTM-30LX'),
    # Hokuyo URG-04LX: steps 44..725 of 1024 per turn, front step 384 (0.352 deg, 240 deg),
    # 20-5600 mm, 10 Hz; +-10 mm to 1 m, 1 % of the distance to 4 m. The old hokuyo_node driver
    # writes no echo as the error code in millimetres.
    LaserProfile('hokuyo_urg04lx', LaserConfig(
        **_layout(44 - 384, 725 - 384, 1024), range_min=0.02, range_max=5.6, noise_std=0.005,
        noise_fraction=0.005, far_range=4.0, dropout=0.01, dropout_far=0.1,
        max_incidence=math.radians(70.0), mixed_pixel_probability=0.5,
        error_encoding='tiny_codes'), 10.0, 'Hokuyo URG-04LX'),
    # Slamtec RPLIDAR A2M8 at 10 Hz: 360 deg in 0.45 deg steps, 0.15-12 m; distance
    # resolution < 1 % of the distance; 8 m reach for the older units (R3 and before).
    LaserProfile('rplidar_a2', LaserConfig(
        **_layout(-400, 399, 800), range_min=0.15, range_max=12.0, noise_fraction=0.005,
        far_range=8.0, dropout=0.01, dropout_far=0.1, max_incidence=math.radians(70.0),
        mixed_pixel_probability=0.3), 10.0, 'Slamtec RPLIDAR A2M8'),
    # ROBOTIS LDS-01 (HLS-LFCD2, the TurtleBot3's laser) at 5 Hz (300 rpm): 360 deg in 1 deg
    # steps from 0 (its driver's 360 readings, angle_min 0), 0.12-3.5 m; accuracy +-15 mm to
    # 0.5 m, +-5 % to 3.5 m, taken as two standard deviations (the data sheet gives no sigma).
    LaserProfile('lds_01', LaserConfig(
        **_layout(0, 359, 360), range_min=0.12, range_max=3.5, noise_std=0.0075,
        noise_fraction=0.025, dropout=0.01, max_incidence=math.radians(70.0),
        mixed_pixel_probability=0.3), 5.0, 'ROBOTIS LDS-01'),
)}

#: The profiles' names, ``ideal`` first.
LASER_PROFILE_NAMES = tuple(LASER_PROFILES)

#: The `LaserConfig` fields a profile's user may override (``laser_config``): the artefacts and
#: the mount (the ``pybullet_world`` node's ``laser_x``, ``laser_z``, ``laser_upside_down``...);
#: not the driver's codes.
OVERRIDABLE_FIELDS = tuple(item.name for item in fields(LaserConfig)
                           if item.name != 'error_codes')


def laser_profile(name):
    """
    Return the `LaserProfile` called ``name``.

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones.

    """
    return named_profile(LASER_PROFILES, 'laser profile', name)


def laser_config(name, **overrides):
    """
    Return a profile's `LaserConfig`, with some fields overridden.

    Parameters
    ----------
    name : str
        A profile of `LASER_PROFILES`.
    **overrides
        `OVERRIDABLE_FIELDS` to change. A NaN float, an empty string or None keeps the
        profile's value (how the ``pybullet_world`` node says "not set").

    Returns
    -------
    LaserConfig

    Raises
    ------
    ValueError
        For an unknown profile or field, or a value the laser does not accept.

    """
    laser = laser_profile(name).laser
    unknown = sorted(set(overrides) - set(OVERRIDABLE_FIELDS))
    if unknown:
        raise ValueError(f'cannot override {", ".join(unknown)} of a laser profile; fields: '
                         f'{", ".join(OVERRIDABLE_FIELDS)}')
    changes = {key: value for key, value in overrides.items()
               if not (value is None or value == '' or
                       (isinstance(value, float) and math.isnan(value)))}
    return replace(laser, **changes) if changes else laser
