"""acdf's environment light and BRDF samplers as Mitsuba 3 plugins, over the batched module.

    import mitsuba as mi
    mi.set_variant("scalar_rgb")          # or "llvm_ad_rgb", see below
    import acdf.mitsuba
    acdf.mitsuba.register()
    emitter = mi.load_dict({"type": "acdf_envmap", "filename": "sky.exr", "strategy": "adaptive"})

`acdf_envmap` takes Mitsuba's `envmap` parameters `filename`, `scale` (a number) and `to_world`
(a rotation: directions are mapped by its linear part, as `envmap` does), plus `strategy` (a name of
`acdf.environment_samplings()`; adaptive by default) and the table options of `acdf.EnvironmentLight` (`epsilon`, `normal_rows`,
`normal_columns`, `block_size`). `compensated` (and `local-compensated`, per normal cell) is
Mitsuba's `mis_compensation`: its emitter samples and pdf leave out the directions where the map is below its
mean, which BSDF sampling covers, so it is unbiased only under integrators that combine emitter and
BSDF sampling by MIS (`path`, `volpath`, `direct` with both sample counts > 0); rays leaving the
light (`sample_ray`) use the complete table. The map's frame is Mitsuba's:
+Y up, phi = 0 along -Z, phi growing towards +X. The radiance of a direction is acdf's: the
nearest pixel times the scale, the function the tables are built for (Mitsuba's `envmap`
interpolates bilinearly, so the two agree wherever the map is constant around a direction).

Mitsuba does not tell Python emitters the scene's bounds: load scenes with `acdf.mitsuba.load_dict`
or `load_file` (mi.load_* that then give them to acdf_envmap) where rays leave the light
(`sample_ray`, light tracing); path tracing needs no bounds.

`acdf_measured` takes `filename` (a MERL .binary or an RGL .bsdf), `sampling` (adaptive,
uniform, rgl, cosine) and, for the tables, every table option of `acdf.TabulatedBrdfSampler`
(`acdf.table_options()`: `layout`, `theta_half`, `chi2_epsilon`, ..., as a scene file's "table" names
them). Any other parameter is refused, by either plugin. Mitsuba's si.wi (towards the viewer) is acdf's wo and Mitsuba's wo (towards
the light) acdf's wi; Mitsuba's eval is f times the cosine of its wo.

In the JIT variants `acdf_envmap` with a table that is a cascade over the pixels (uniform, adaptive,
compensated) or none (uniform-sphere) samples and evaluates it with drjit operations over the table's
arrays, which Mitsuba traces into its kernels (NativeEnvmap). The other strategies and
`acdf_measured` make one batched acdf call per wavefront, which reads the arrays into numpy: they
need drjit's evaluated mode, which `register()` turns on in the thread that calls it (drjit's flags
are per thread, and Mitsuba may build plugins on others). `register(batched_plugins=False)` leaves
drjit's symbolic modes as they are, for renders 4-6x faster, and refuses the batched plugins.
"""

import numpy as np

import acdf

_STRATEGIES = tuple(s["name"] for s in acdf.environment_samplings())


def _mi():
    import mitsuba as mi  # imported late: acdf itself does not need mitsuba

    return mi


def evaluated_mode():
    """Lets Python plugins read their arguments: drjit loops and virtual calls are evaluated
    wavefront by wavefront instead of recorded as symbolic kernels (JIT variants only)."""
    import drjit as dr

    dr.set_flag(dr.JitFlag.SymbolicLoops, False)
    dr.set_flag(dr.JitFlag.SymbolicCalls, False)
    dr.set_flag(dr.JitFlag.SymbolicConditionals, False)


def _rows(vector):
    """A drjit 3-vector (scalar or wide) as a float64 (n, 3) numpy array."""
    a = np.asarray(vector, dtype=np.float64)
    return a.reshape(1, 3) if a.ndim == 1 else np.ascontiguousarray(a.T)


def _rows_like(vector, n):
    """_rows of a field of an interaction, broadcast to n rows (a default interaction's fields are
    empty in JIT variants: those count as zero)."""
    a = _rows(vector)
    return np.zeros((n, 3)) if a.size == 0 else np.broadcast_to(a, (n, 3))


def _variates(point):
    a = np.asarray(point, dtype=np.float32)
    return a.reshape(1, 2) if a.ndim == 1 else np.ascontiguousarray(a.T)


def _vector(mi, rows):
    if not mi.variant().startswith("scalar"):
        return mi.Vector3f(rows[:, 0], rows[:, 1], rows[:, 2])
    return mi.Vector3f(*rows[0])


def _float(mi, values):
    return mi.Float(values) if not mi.variant().startswith("scalar") else mi.Float(values[0])


def _color(mi, rows):
    rows = np.asarray(rows, dtype=np.float32)
    if not mi.variant().startswith("scalar"):
        return mi.Color3f(rows[:, 0], rows[:, 1], rows[:, 2])
    return mi.Color3f(*rows[0])


def _refuse(plugin, problem):
    raise ValueError(f"{plugin}: {problem}")


def _refuse_unknown(plugin, props, known):
    """Refuses parameters the plugin does not read (Mitsuba would otherwise drop them silently)."""
    unknown = sorted(set(props.keys()) - set(known))
    if unknown:
        _refuse(plugin, f"unsupported parameter(s) {', '.join(unknown)}; it takes {', '.join(known)}")


def _table_options(props, kinds):
    """The acdf table options among props (kinds: name -> type), as keyword arguments."""
    return {name: kind(props[name]) for name, kind in kinds.items() if name in props}


_ENVMAP_TABLE_OPTIONS = {"epsilon": float, "normal_rows": int, "normal_columns": int, "block_size": int}
_KINDS = {"count": int, "number": float, "boolean": bool, "name": str}
_MEASURED_TABLE_OPTIONS = {option["key"]: _KINDS[option["type"]] for option in acdf.table_options()}


def _strategy_of(props):
    return str(props["strategy"]) if "strategy" in props else "adaptive"


def _make_envmap_classes():
    """(AcdfEnvmap, BatchedEnvmap, NativeEnvmap) of the current variant."""
    mi = _mi()
    import drjit as dr

    class AcdfEnvmap(mi.Emitter):
        """What both implementations share: the parameters, the light, the scene's bounds."""

        def __init__(self, props):
            mi.Emitter.__init__(self, props)
            name = "acdf_envmap"
            _refuse_unknown(name, props, ["filename", "scale", "to_world", "strategy", *_ENVMAP_TABLE_OPTIONS])
            if "filename" not in props:
                _refuse(name, "needs a filename")
            filename = str(props["filename"])
            scale = props["scale"] if "scale" in props else 1.0
            if isinstance(scale, bool) or not isinstance(scale, (int, float)):
                _refuse(name, f"scale must be a number (textured scales are not supported), got {type(scale).__name__}")
            strategy = _strategy_of(props)
            if strategy not in _STRATEGIES:
                _refuse(name, f"unknown strategy {strategy!r}; one of {', '.join(_STRATEGIES)}")
            table = _table_options(props, _ENVMAP_TABLE_OPTIONS)
            to_world = props["to_world"] if "to_world" in props else mi.ScalarTransform4f()
            linear = np.array(to_world.matrix, dtype=np.float64)[:3, :3]
            if not np.allclose(linear @ linear.T, np.eye(3), atol=1e-5):
                _refuse(name, "to_world must be a rotation")
            self.world_from_map = linear
            self.map_from_world = linear.T
            self.strategy = strategy
            self.scale = float(scale)
            self.incomplete = strategy in ("compensated", "local-compensated")
            # acdf.FileError (an OSError) names the file; bad options raise ValueError.
            self.light = acdf.EnvironmentLight.load(filename, strategy=strategy, scale=float(scale), **table)
            self.bounds = None  # the scene's bounding sphere (center, radius), for rays leaving the light
            self.m_flags = mi.EmitterFlags.Infinite | mi.EmitterFlags.SpatiallyVarying

        def set_scene(self, scene):
            """Mitsuba calls this on its C++ emitters only; load_dict and load_file below call it."""
            box = scene.bbox()
            if box.valid():
                sphere = box.bounding_sphere()
                self.bounds = (np.asarray(sphere.center, dtype=np.float64).reshape(3),
                               max(float(sphere.radius) * (1 + 1e-4), 1e-4))

        def bbox(self):
            return mi.ScalarBoundingBox3f()

        def to_string(self):
            return f"AcdfEnvmap[strategy={self.strategy}, bytes={self.light.bytes}]"

    class BatchedEnvmap(AcdfEnvmap):
        """Every strategy, in every variant: one batched acdf call per wavefront (in JIT variants under
        evaluated mode: register())."""

        def _to_map(self, world_dirs):
            """Map-frame rows, and which of them are directions (a wavefront's inactive lanes may not be)."""
            ok, rows = _usable(_rows(world_dirs))
            return ok, rows @ self.map_from_world.T

        def _normals(self, it):
            if not self.strategy.startswith("local"):
                return None
            n = _rows(it.n)
            if n.size == 0:
                return None
            n = n @ self.map_from_world.T
            return n if np.all(np.isfinite(n)) and np.all(np.linalg.norm(n, axis=1) > 0.5) else None

        def _radiance(self, world_dirs):
            ok, dirs = self._to_map(world_dirs)
            return _color(mi, np.where(ok[:, None], self.light.eval(dirs), 0.0))

        def eval(self, si, active=True):
            return self._radiance(-si.wi)

        def eval_direction(self, it, ds, active=True):
            return self._radiance(ds.d)

        def pdf_direction(self, it, ds, active=True):
            ok, dirs = self._to_map(ds.d)
            pdf = self.light.pdf(dirs, normal=self._normals(it), allow_incomplete_pdf=self.incomplete)
            return _float(mi, np.where(ok, pdf, 0.0))

        def sample_direction(self, it, sample, active=True):
            dirs, radiance, pdf = self.light.sample(_variates(sample), normal=self._normals(it),
                                                   allow_incomplete_pdf=self.incomplete)
            world = dirs @ self.world_from_map.T
            p = _rows_like(it.p, len(pdf))
            # Beyond any scene: the shadow ray must reach past every occluder, and the scene's
            # bounds are not known here (set_scene is not called on Python emitters). 1e15 keeps
            # |p - ds.p|^2 finite in single precision and the direction exact to rounding.
            dist = np.full(len(pdf), _FAR)
            weight = np.where(pdf[:, None] > 0, radiance / np.where(pdf > 0, pdf, 1.0)[:, None], 0.0)
            jit = dr.is_jit_v(mi.Float)
            ds = dr.zeros(mi.DirectionSample3f, len(pdf)) if jit else mi.DirectionSample3f()
            d = _vector(mi, world)
            ds.d = d
            ds.dist = _float(mi, dist)
            ds.p = _vector(mi, p + world * dist[:, None])
            ds.n = -d
            ds.pdf = _float(mi, pdf)
            ds.time = it.time
            ds.delta = False
            ds.emitter = mi.EmitterPtr(self) if jit else self
            return ds, _color(mi, weight)

        def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
            if self.bounds is None:
                _refuse("acdf_envmap", "rays leaving the light need the scene's bounding sphere, which Mitsuba "
                        "does not give Python emitters: load the scene with acdf.mitsuba.load_dict or load_file")
            center, radius = self.bounds
            offset = _variates(mi.warp.square_to_uniform_disk_concentric(sample2)).astype(np.float64)
            dirs, radiance, pdf = self.light.sample(_variates(sample3))
            d = -(dirs @ self.world_from_map.T)  # the ray travels away from the light's direction
            # An orthonormal basis perpendicular to d: the ray starts on the disk of the scene's sphere.
            helper = np.where(np.abs(d[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
            s = np.cross(d, helper)
            s /= np.linalg.norm(s, axis=1, keepdims=True)
            t = np.cross(d, s)
            origin = center + (offset[:, :1] * s + offset[:, 1:] * t - d) * radius
            area = np.pi * radius**2
            weight = np.where(pdf[:, None] > 0, radiance * area / np.where(pdf > 0, pdf, 1.0)[:, None], 0.0)
            ray = mi.Ray3f(_vector(mi, origin), _vector(mi, d), time)
            return ray, _color(mi, weight)

    class NativeEnvmap(AcdfEnvmap):
        """JIT variants, the strategies of _NATIVE_STRATEGIES: acdf's table as arrays of the variant,
        sampled and evaluated by drjit operations that Mitsuba records into its kernels with the rest
        of the path (no Python or acdf call per wavefront; drjit's symbolic modes stay as they are)."""

        def __init__(self, props):
            AcdfEnvmap.__init__(self, props)
            light = self.light
            width, height = light.map.width, light.map.height
            rgb = light.map.rgb.reshape(-1) * np.float32(self.scale)
            self.radiance = mi.Float(rgb.astype(np.float32))
            self.width, self.height = width, height
            self.m = [[float(x) for x in row] for row in self.world_from_map]
            if self.strategy == "uniform-sphere" or light.emits_nothing:
                self.table = self.complete = None
            else:
                self.table = _DrjitTable(mi, light.cascade_arrays(allow_incomplete_pdf=self.incomplete), width, height)
                self.complete = (_DrjitTable(mi, light.cascade_arrays(), width, height) if self.incomplete
                                 else self.table)

        def _to_world(self, d):
            m = self.m
            return mi.Vector3f(m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z,
                               m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z,
                               m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z)

        def _to_map(self, d):
            m = self.m
            return mi.Vector3f(m[0][0] * d.x + m[1][0] * d.y + m[2][0] * d.z,
                               m[0][1] * d.x + m[1][1] * d.y + m[2][1] * d.z,
                               m[0][2] * d.x + m[1][2] * d.y + m[2][2] * d.z)

        def _radiance_of_pixel(self, row, column, active):
            return dr.gather(mi.Color3f, self.radiance, row * self.width + column, active)

        def _radiance(self, world_dir, active):
            row, column = _pixel_of(mi, self._to_map(world_dir), self.width, self.height)
            return self._radiance_of_pixel(row, column, active)

        def _sample(self, table, u, active):
            """Map-frame direction, its pixel and pdf per steradian (0 for a light that emits nothing)."""
            if self.strategy == "uniform-sphere":
                d = mi.warp.square_to_uniform_sphere(u)
                row, column = _pixel_of(mi, d, self.width, self.height)
                return d, row, column, mi.Float(dr.inv_four_pi)
            if table is None:
                zero = mi.UInt32(0)
                return mi.Vector3f(0, 0, 1), zero, zero, mi.Float(0)
            return table.sample(u, active)

        def eval(self, si, active=True):
            return self._radiance(-si.wi, active)

        def eval_direction(self, it, ds, active=True):
            return self._radiance(ds.d, active)

        def pdf_direction(self, it, ds, active=True):
            if self.strategy == "uniform-sphere":
                return mi.Float(dr.inv_four_pi)
            if self.table is None:
                return mi.Float(0)
            return self.table.pdf(self._to_map(ds.d), active)

        def sample_direction(self, it, sample, active=True):
            d_map, row, column, pdf = self._sample(self.table, sample, active)
            d = self._to_world(d_map)
            ds = dr.zeros(mi.DirectionSample3f)
            ds.d = d
            ds.dist = mi.Float(_FAR)
            # A default interaction's fields are empty in JIT variants: those count as zero.
            ds.p = (it.p if dr.width(it.p) else mi.Point3f(0)) + d * _FAR
            ds.n = -d
            ds.pdf = pdf
            ds.time = it.time
            ds.delta = mi.Bool(False)
            ds.emitter = mi.EmitterPtr(self)
            found = active & (pdf > 0)
            weight = dr.select(found, self._radiance_of_pixel(row, column, found) / dr.select(found, pdf, 1), 0)
            return ds, weight

        def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
            if self.bounds is None:
                _refuse("acdf_envmap", "rays leaving the light need the scene's bounding sphere, which Mitsuba "
                        "does not give Python emitters: load the scene with acdf.mitsuba.load_dict or load_file")
            center, radius = self.bounds
            d_map, row, column, pdf = self._sample(self.complete, sample3, active)
            d = -self._to_world(d_map)  # the ray travels away from the light's direction
            frame = mi.Frame3f(d)
            offset = mi.warp.square_to_uniform_disk_concentric(sample2)
            origin = mi.Point3f(*[float(x) for x in center]) + (frame.s * offset.x + frame.t * offset.y - d) * radius
            found = active & (pdf > 0)
            area = dr.pi * radius**2
            weight = dr.select(found, self._radiance_of_pixel(row, column, found) * area / dr.select(found, pdf, 1), 0)
            return mi.Ray3f(origin, d, time), weight

    return AcdfEnvmap, BatchedEnvmap, NativeEnvmap


# The strategies NativeEnvmap samples: a table that is a cascade over the pixels, or none.
_NATIVE_STRATEGIES = ("uniform-sphere", "uniform", "adaptive", "compensated")
# How far from a pixel's edges (a fraction of the pixel) NativeEnvmap places its samples: a float32
# direction's pixel, found again by pdf_direction, is then the pixel it was drawn in (float32 angles
# err by a few 1e-7 rad, 1e-3 of a pixel of a 8192 x 4096 map). The radiance and the pdf are
# constant on a pixel, so where in it a sample lies changes no estimate of the map's light; against
# a BRDF that varies inside a pixel, the shift is of order 1e-3 of the pixel's share of the light.
_PIXEL_MARGIN = 2e-3


def _pixel_of(mi, d, width, height):
    """The pixel (row, column) of a map-frame direction: theta from +Y, phi from -Z towards +X
    (acdf's lat-long mapping, envmap/lat_long.h), in the variant's float arithmetic."""
    import drjit as dr

    theta = dr.atan2(dr.sqrt(d.x * d.x + d.z * d.z), d.y)
    phi = dr.atan2(d.x, -d.z)
    phi = dr.select(phi < 0, phi + dr.two_pi, phi)
    row = dr.minimum(mi.UInt32(dr.maximum(theta * (height * dr.inv_pi), 0)), height - 1)
    column = dr.minimum(mi.UInt32(dr.maximum(phi * (width * dr.inv_two_pi), 0)), width - 1)
    return row, column


class _DrjitCdfs:
    """One axis of a cascade (EnvironmentLight.cascade_arrays): its 1D CDFs laid end to end."""

    def __init__(self, mi, arrays, cells):
        self.mi = mi
        self.start = mi.UInt32(arrays["start"])
        self.vertex = mi.UInt32(arrays["vertex"])
        self.value = mi.Float(arrays["value"])
        self.last = len(arrays["vertex"]) - 1
        self.cells = cells

    def bounds(self, cdf, active):
        """Breakpoints [first, end) of CDF `cdf`."""
        import drjit as dr

        return (dr.gather(self.mi.UInt32, self.start, cdf, active),
                dr.gather(self.mi.UInt32, self.start, cdf + 1, active))

    def _last_at_most(self, first, end, of, threshold):
        """The last breakpoint k of [first, end) with of[k] <= threshold (of: the values or the
        vertices, non-decreasing in each CDF): one binary search over every CDF of the axis, where
        the breakpoints before `first` count as below and those from `end` on as above."""
        import drjit as dr

        kind = self.mi.Float if of is self.value else self.mi.UInt32
        above = dr.binary_search(0, self.last, lambda k: (k < first) | ((k < end) & (dr.gather(kind, of, k) <= threshold)))
        return above - 1

    def interval_of_variate(self, first, end, u):
        """Interval k of the CDF with value[k] <= u < value[k + 1] (u in [0, 1)): it has mass."""
        return self._last_at_most(first, end, self.value, u)

    def interval_of_cell(self, first, end, cell):
        return self._last_at_most(first, end, self.vertex, cell)

    def interval(self, k, active):
        """(value at k, at k + 1, vertex at k, at k + 1) and the density on the axis' unit interval."""
        import drjit as dr

        mi = self.mi
        lo, hi = dr.gather(mi.Float, self.value, k, active), dr.gather(mi.Float, self.value, k + 1, active)
        a, b = dr.gather(mi.UInt32, self.vertex, k, active), dr.gather(mi.UInt32, self.vertex, k + 1, active)
        density = (hi - lo) * self.cells / mi.Float(dr.maximum(b - a, 1))
        return lo, hi, a, b, density


class _DrjitTable:
    """An acdf table of a map's pixels (a two-level cascade: rows, then the columns of each row
    interval) in a JIT variant's arrays. Its density on the unit square is that of acdf's
    EnvironmentTable; per steradian it is divided by W H times the pixel's solid angle, and inside a
    pixel samples are uniform in solid angle, as acdf's (envmap/environment_table.h)."""

    def __init__(self, mi, levels, width, height):
        self.mi = mi
        self.rows = _DrjitCdfs(mi, levels[0], height)
        self.columns = _DrjitCdfs(mi, levels[1], width)
        self.width, self.height = width, height
        cos_edge = np.cos(np.pi * np.arange(height + 1) / height)
        cos_edge[0], cos_edge[-1] = 1.0, -1.0
        solid_angle = (cos_edge[:-1] - cos_edge[1:]) * (2 * np.pi / width)
        # Directions are placed in double: in float32, cos theta near a pole cannot tell a pixel's rows apart.
        self.cos_edge = mi.Float64(cos_edge)
        self.pdf_scale = mi.Float((1.0 / (float(width) * height * solid_angle)).astype(np.float32))

    def _density(self, row, row_density, column_density, active):
        import drjit as dr

        return row_density * column_density * dr.gather(self.mi.Float, self.pdf_scale, row, active)

    def sample(self, u, active):
        import drjit as dr

        mi = self.mi
        below_one = float(np.nextafter(np.float32(1), np.float32(0)))
        u0, u1 = dr.clip(u.x, 0, below_one), dr.clip(u.y, 0, below_one)
        k = self.rows.interval_of_variate(0, self.rows.last + 1, u0)
        lo, hi, a, b, row_density = self.rows.interval(k, active)
        row_at = mi.Float(a) + (u0 - lo) / (hi - lo) * mi.Float(b - a)
        row = dr.clip(mi.UInt32(row_at), a, b - 1)
        first, end = self.columns.bounds(k, active)
        j = self.columns.interval_of_variate(first, end, u1)
        lo, hi, a, b, column_density = self.columns.interval(j, active)
        column_at = mi.Float(a) + (u1 - lo) / (hi - lo) * mi.Float(b - a)
        column = dr.clip(mi.UInt32(column_at), a, b - 1)
        down = dr.clip(row_at - mi.Float(row), _PIXEL_MARGIN, 1 - _PIXEL_MARGIN)
        right = dr.clip(column_at - mi.Float(column), _PIXEL_MARGIN, 1 - _PIXEL_MARGIN)

        top, bottom = dr.gather(mi.Float64, self.cos_edge, row, active), dr.gather(mi.Float64, self.cos_edge, row + 1, active)
        cos_theta = top + mi.Float64(down) * (bottom - top)
        sin_theta = dr.sqrt(dr.maximum(0, (1 - cos_theta) * (1 + cos_theta)))
        sin_phi, cos_phi = dr.sincos((mi.Float64(column) + mi.Float64(right)) * (2 * np.pi / self.width))
        d = mi.Vector3f(mi.Float(sin_theta * sin_phi), mi.Float(cos_theta), mi.Float(-sin_theta * cos_phi))
        return d, row, column, self._density(row, row_density, column_density, active)

    def pdf(self, d, active):
        row, column = _pixel_of(self.mi, d, self.width, self.height)
        k = self.rows.interval_of_cell(0, self.rows.last + 1, row)
        row_density = self.rows.interval(k, active)[4]
        first, end = self.columns.bounds(k, active)
        j = self.columns.interval_of_cell(first, end, column)
        return self._density(row, row_density, self.columns.interval(j, active)[4], active)


_FAR = 1e15
_envmap_classes = []  # AcdfEnvmap of each variant register() was called in

_SAMPLINGS = ("adaptive", "uniform", "rgl", "cosine")


def _usable(rows):
    """Rows that are directions (finite, not zero: a wavefront's inactive lanes may be neither),
    and the rows with the others replaced by +z so that acdf accepts them."""
    ok = np.all(np.isfinite(rows), axis=1) & (np.linalg.norm(rows, axis=1) > 0.5)
    return ok, np.where(ok[:, None], rows, [[0.0, 0.0, 1.0]])


def _make_measured_class():
    mi = _mi()
    import drjit as dr

    class AcdfMeasured(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            name = "acdf_measured"
            _refuse_unknown(name, props, ["filename", "sampling", *_MEASURED_TABLE_OPTIONS])
            if "filename" not in props:
                _refuse(name, "needs a filename (MERL .binary or RGL .bsdf)")
            filename = str(props["filename"])
            sampling = str(props["sampling"]) if "sampling" in props else "adaptive"
            if sampling not in _SAMPLINGS:
                _refuse(name, f"unknown sampling {sampling!r}; one of {', '.join(_SAMPLINGS)}")
            if filename.endswith(".binary"):
                model = acdf.MerlBrdf.load(filename)
            elif filename.endswith(".bsdf"):
                model = acdf.RglBrdf.load(filename)  # refuses anisotropic files, naming the file
            else:
                _refuse(name, f"{filename}: expected a MERL .binary or an RGL .bsdf file")
            if sampling in ("rgl", "cosine") and _table_options(props, _MEASURED_TABLE_OPTIONS):
                _refuse(name, f"table options ({', '.join(_table_options(props, _MEASURED_TABLE_OPTIONS))}) "
                        f"apply to adaptive and uniform sampling, not {sampling}")
            if sampling == "rgl":
                if not isinstance(model, acdf.RglBrdf):
                    _refuse(name, "sampling 'rgl' needs an RGL .bsdf file")
                self.sampler = acdf.RglBrdfSampler(model)
            elif sampling == "cosine":
                self.sampler = acdf.CosineBrdfSampler(model)
            else:
                table = {"layout": "isotropic" if model.isotropic else "4d",
                         **_table_options(props, _MEASURED_TABLE_OPTIONS)}
                self.sampler = acdf.TabulatedBrdfSampler(model, method=sampling, **table)
            self.sampling = sampling
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [flags]
            self.m_flags = flags

        # Mitsuba's si.wi points to the viewer and its wo to the light; acdf's wo is the viewer
        # and wi the light. Mitsuba's eval includes the cosine of the light direction; acdf's does not.
        def _pair(self, si, wo):
            viewer, light = _rows(si.wi), _rows(wo)
            n = max(len(viewer), len(light))
            viewer, light = np.broadcast_to(viewer, (n, 3)), np.broadcast_to(light, (n, 3))
            ok_v, viewer = _usable(viewer)
            ok_l, light = _usable(light)
            up = ok_v & ok_l & (viewer[:, 2] > 0) & (light[:, 2] > 0)
            return up, viewer, light

        def eval(self, ctx, si, wo, active=True):
            up, viewer, light = self._pair(si, wo)
            f = self.sampler.eval(viewer, light) * np.maximum(light[:, 2], 0.0)[:, None]
            return _color(mi, np.where(up[:, None], f, 0.0))

        def pdf(self, ctx, si, wo, active=True):
            up, viewer, light = self._pair(si, wo)
            return _float(mi, np.where(up, self.sampler.pdf(viewer, light), 0.0))

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            u = _variates(sample2)
            ok, viewer = _usable(np.broadcast_to(_rows(si.wi), (len(u), 3)))
            ok &= viewer[:, 2] > 0
            light, weight, pdf = self.sampler.sample(viewer, u)
            ok &= (pdf > 0) & (light[:, 2] > 0)
            jit = dr.is_jit_v(mi.Float)
            bs = dr.zeros(mi.BSDFSample3f, len(u)) if jit else mi.BSDFSample3f()
            bs.wo = _vector(mi, light)
            bs.pdf = _float(mi, np.where(ok, pdf, 0.0))
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            return bs, _color(mi, np.where(ok[:, None], weight, 0.0))

        def to_string(self):
            return f"AcdfMeasured[sampling={self.sampling}, bytes={self.sampler.bytes}]"

    return AcdfMeasured


def register(batched_plugins=True):
    """Registers acdf_envmap and acdf_measured with Mitsuba for the current variant (call after
    mi.set_variant, in the thread that renders).

    In JIT variants, batched_plugins=True turns on the evaluated mode the batched plugins need
    (acdf_measured, acdf_envmap with local, local-compensated, alias or hierarchical). False leaves
    drjit's symbolic modes as they are, so that Mitsuba records acdf_envmap's drjit sampling into
    its kernels with the rest of the path (4-6x faster renders); the batched plugins are then
    refused, naming this option."""
    mi = _mi()
    base, batched, native = _make_envmap_classes()
    _envmap_classes.append(base)
    jit = not mi.variant().startswith("scalar")
    if jit and batched_plugins:
        evaluated_mode()
    measured = _make_measured_class()

    def allowed(plugin, cls, what):
        def make(props):
            if jit and not batched_plugins:
                _refuse(plugin, f"{what(props)} makes batched acdf calls, which need drjit's evaluated mode: call "
                        "acdf.mitsuba.register() without batched_plugins=False")
            return cls(props)

        return make

    batched_envmap = allowed("acdf_envmap", batched, lambda props: f"strategy {_strategy_of(props)!r}")
    mi.register_emitter("acdf_envmap", lambda props: native(props) if jit and _strategy_of(props) in _NATIVE_STRATEGIES
                        else batched_envmap(props))
    mi.register_bsdf("acdf_measured", allowed("acdf_measured", measured, lambda props: "the plugin"))


def _with_bounds(scene):
    for emitter in scene.emitters():
        if isinstance(emitter, tuple(_envmap_classes)):
            emitter.set_scene(scene)
    return scene


def load_dict(scene_dict, **kwargs):
    """mi.load_dict, then gives acdf_envmap emitters the scene's bounding sphere (needed by
    sample_ray: light tracing, e.g. Mitsuba's ptracer; path tracing does not need it)."""
    return _with_bounds(_mi().load_dict(scene_dict, **kwargs))


def load_file(path, **kwargs):
    """mi.load_file, then as load_dict."""
    return _with_bounds(_mi().load_file(path, **kwargs))
