"""The Mitsuba 3 twins of thinlens.scn and motion.scn (bench/peers/README.md).

Each function returns a dict for mi.load_dict. Change a scene here and in its .scn
together. The conventions that make the two renderers see the same picture:

- camera: Snell's right = cross(forward, up) and Mitsuba's look_at basis give the
  same image orientation; Snell's `fov` is horizontal, so fov_axis = "x"; the
  thin lens is pbrt's in both, with Snell's `aperture` a diameter (Mitsuba's
  aperture_radius = aperture / 2) and the focal plane perpendicular to the view
  direction at focal_distance / focus_distance.
- film: Snell averages the camera samples of a pixel uniformly over its square,
  which is Mitsuba's `box` reconstruction filter.
- area light: Snell's parallelogram corner + u·edge1 + v·edge2, one-sided towards
  cross(edge1, edge2), is a Mitsuba `rectangle` ([-1, 1]², normal +z) placed by the
  affine map with columns edge1/2, edge2/2, normalize(cross(edge1, edge2)) and the
  centre, carrying an `area` emitter of the same radiance (one-sided).
- the infinite floor plane is a rectangle of half-size 2000: beyond it the light's
  contribution is below 1e-12 of the radiance.
- `direct` integrator (1 emitter + 1 BSDF sample, MIS) against Snell's ray tree with
  max_depth 0; black background in both (Snell's background lights no diffuse
  surface, Mitsuba has no environment emitter here).
"""

import numpy as np

WIDTH, HEIGHT = 400, 300
CAMERA = dict(origin=(0, 2, -6), target=(0, 0.6, 0), up=(0, 1, 0), fov=45)
APERTURE = 0.4  # Snell's lens diameter
FOCAL_DISTANCE = 6.16
LIGHT = dict(corner=(-1, 4, -1), edge1=(2, 0, 0), edge2=(0, 0, 2), radiance=(6, 5.7, 5.2))
FLOOR_ALBEDO = 0.6
# (centre, radius, albedo); the first one moves in motion.scn
SPHERES = [
    ((0, 0.6, 0), 0.6, (0.8, 0.25, 0.2)),
    ((-1.5, 0.5, -1.6), 0.5, (0.2, 0.6, 0.3)),
    ((1.4, 0.45, -2.4), 0.45, (0.25, 0.35, 0.8)),
    ((1.7, 0.7, 1.8), 0.7, (0.85, 0.8, 0.3)),
    ((-1.9, 0.8, 2.6), 0.8, (0.75, 0.75, 0.75)),
]
MOTION_TRANSLATE = (1.2, 0, 0)  # sphere 0 over the shutter <0, 1>


def _diffuse(c):
    if not isinstance(c, (tuple, list)):
        c = (c, c, c)
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(c)}}


def _parallelogram_to_world(mi, corner, e1, e2):
    corner, e1, e2 = (np.asarray(v, dtype=float) for v in (corner, e1, e2))
    n = np.cross(e1, e2)
    n /= np.linalg.norm(n)
    centre = corner + 0.5 * e1 + 0.5 * e2
    m = np.identity(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = 0.5 * e1, 0.5 * e2, n, centre
    return mi.ScalarTransform4f(m.tolist())


def _base(mi, sampler, spp, sensor_extra, emitter_samples=1):
    T = mi.ScalarTransform4f
    sensor = {
        "to_world": T().look_at(origin=list(CAMERA["origin"]), target=list(CAMERA["target"]),
                                up=list(CAMERA["up"])),
        "fov": CAMERA["fov"],
        "fov_axis": "x",
        "sampler": {"type": sampler, "sample_count": spp},
        "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
    }
    sensor.update(sensor_extra)
    d = {
        "type": "scene",
        # emitter_samples > 1: that many independent light samples per camera sample (Mitsuba's
        # counterpart of a Snell area light's samples grid, but not stratified); bsdf_samples 1
        "integrator": {"type": "direct", "emitter_samples": emitter_samples, "bsdf_samples": 1},
        "sensor": sensor,
        "light": {
            "type": "rectangle",
            "to_world": _parallelogram_to_world(mi, LIGHT["corner"], LIGHT["edge1"], LIGHT["edge2"]),
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": list(LIGHT["radiance"])}},
            # black from behind (one-sided), as Snell's panel is
            "bsdf": _diffuse(0.0),
        },
        "floor": {
            "type": "rectangle",
            "to_world": T().rotate(axis=[1, 0, 0], angle=-90).scale(2000),  # normal +y at y = 0
            "bsdf": _diffuse(FLOOR_ALBEDO),
        },
    }
    for i, (c, r, a) in enumerate(SPHERES):
        d[f"sphere{i}"] = {"type": "sphere", "center": list(c), "radius": r, "bsdf": _diffuse(a)}
    return d


def thinlens(mi, sampler="independent", spp=256, emitter_samples=1):
    return _base(mi, sampler, spp, {"type": "thinlens", "aperture_radius": APERTURE / 2,
                                    "focus_distance": FOCAL_DISTANCE}, emitter_samples)


def motion(mi, sampler="independent", spp=256, emitter_samples=1):
    """The scene at shutter open; move_sphere() places the moving sphere at time t."""
    return _base(mi, sampler, spp, {"type": "perspective"}, emitter_samples)


def moving_sphere_key():
    return "sphere0"


def sphere_center_at(t):
    c = np.asarray(SPHERES[0][0], dtype=float)
    return (c + t * np.asarray(MOTION_TRANSLATE, dtype=float)).tolist()
