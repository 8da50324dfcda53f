"""acdf's environment light and BRDF samplers as Mitsuba 3 plugins: in drjit in the JIT variants,
over the batched module in the scalar ones.

    import mitsuba as mi
    mi.set_variant("scalar_rgb")          # or "llvm_ad_rgb", see below
    import acdf.mitsuba
    acdf.mitsuba.register()
    emitter = mi.load_dict({"type": "acdf_envmap", "filename": "sky.exr", "strategy": "adaptive"})

`acdf_envmap` takes Mitsuba's `envmap` parameters `filename`, `scale` (a number) and `to_world`
(a rotation: directions are mapped by its linear part, as `envmap` does), plus `strategy` (a name of
`acdf.environment_samplings()`; adaptive by default) and the table options of `acdf.EnvironmentLight` (`epsilon`, `normal_rows`,
`normal_columns`, `block_size`), and portals: nested `rectangle` shapes (windows, doors) whose normal points into
the room the map lights through them (acdf.EnvironmentLight's `portals`), and `portals` ("auto", the
default: the nested ones, or where there are none the openings acdf.find_openings finds in a scene
loaded with acdf.mitsuba.load_dict or load_file; "declared"; "none").
`compensated` (and `local-compensated`, per normal cell) is Mitsuba's `mis_compensation`: its emitter
samples and pdf leave out the directions where the map is below its mean, which BSDF sampling covers,
so it is unbiased only under integrators that combine emitter and BSDF sampling by MIS (`path`,
`volpath`, `direct` with both sample counts > 0); rays leaving the light (`sample_ray`) use the
complete table. The map's frame is Mitsuba's:
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

In the JIT variants `acdf_envmap`, whatever its strategy, samples and evaluates its table (a cascade
over the pixels: uniform, adaptive, compensated; alias tables over the rows and the row's columns:
alias; a mip pyramid of the pixels: hierarchical; one per normal cell over blocks of pixels: local,
local-compensated, each lane's from it.n; or none: uniform-sphere), and its portals' tables
(EnvironmentLight.portal_arrays, from each lane's it.p), with drjit operations over the
tables' arrays, which Mitsuba traces into its kernels with drjit's symbolic modes on (NativeEnvmap);
so does `acdf_measured`, whatever its sampling (acdf's half-vector table, the RGL file's own warps or
cosine-weighted: NativeMeasured), whose BRDF values are, for an RGL file, those of Mitsuba's
`measured` plugin loaded from the same file, for a MERL file its table's in drjit. The scalar
variants' plugins (BatchedEnvmap, BatchedMeasured) call acdf's batched methods with one row per lane.
"""

import drjit as dr  # Mitsuba's array library, installed with it
import numpy as np

import acdf

_STRATEGIES = tuple(s["name"] for s in acdf.environment_samplings())


def _mi():
    import mitsuba as mi  # imported late: acdf itself does not need mitsuba

    return mi


# The batched classes run in the scalar variants only: each call is one lane, one row of acdf's batches.
def _rows(vector):
    """A scalar variant's 3-vector as a float64 (1, 3) numpy array."""
    return np.asarray(vector, dtype=np.float64).reshape(1, 3)


def _variates(point):
    return np.asarray(point, dtype=np.float32).reshape(1, 2)


def _vector(mi, rows):
    return mi.Vector3f(*rows[0])


def _float(mi, values):
    return mi.Float(values[0])


def _color(mi, rows):
    return mi.Color3f(*np.asarray(rows, dtype=np.float32)[0])


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
    class AcdfEnvmap(mi.Emitter):
        """What both implementations share: the parameters, the light (which the native one releases
        once its arrays are in drjit), the scene's bounds."""

        def __init__(self, props):
            mi.Emitter.__init__(self, props)
            name = "acdf_envmap"
            portal_names = [key for key in props.keys() if isinstance(props[key], mi.Shape)]
            _refuse_unknown(name, props, ["filename", "scale", "to_world", "strategy", "portals",
                                          *_ENVMAP_TABLE_OPTIONS, *portal_names])
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
            self.portal_source = str(props["portals"]) if "portals" in props else acdf.portal_sources[0]
            if self.portal_source not in acdf.portal_sources:
                _refuse(name, f"unknown portals {self.portal_source!r}; one of {', '.join(acdf.portal_sources)}")
            self.openings = None  # set_scene's acdf.find_openings result, where it searched
            self.light_file, self.light_options = filename, {"strategy": strategy, "scale": float(scale), **table}
            self.bounds = None  # the scene's bounding sphere (center, radius), for rays leaving the light
            self.m_flags = mi.EmitterFlags.Infinite | mi.EmitterFlags.SpatiallyVarying
            self._load([] if self.portal_source == "none" else
                       [_portal_of(mi, key, props[key]) for key in portal_names])

        def _load(self, portals):
            """acdf's light with these portals (world frame)."""
            self.portals = portals
            # acdf's light works in the map's frame: its world is this plugin's map frame.
            in_map = [{key: self.map_from_world @ vector for key, vector in portal.items()} for portal in self.portals]
            # acdf.FileError (an OSError) names the file; bad options raise ValueError.
            self.light = acdf.EnvironmentLight.load(self.light_file, portals=in_map, **self.light_options)

        def set_scene(self, scene):
            """Mitsuba calls this on its C++ emitters only; load_dict and load_file below call it.
            The scene's bounds, and under portals "auto" with none declared its openings
            (acdf.find_openings), which become the light's portals."""
            box = scene.bbox()
            if box.valid():
                sphere = box.bounding_sphere()
                self.bounds = (np.asarray(sphere.center, dtype=np.float64).reshape(3),
                               max(float(sphere.radius) * (1 + 1e-4), 1e-4))
            if self.portal_source == "auto" and not self.portals:
                self.openings = _find_openings(mi, scene)
                if self.openings is not None and self.openings["portals"]:
                    self._load([{key: np.asarray(vector, dtype=np.float64) for key, vector in portal.items()}
                                for portal in self.openings["portals"]])

        def bbox(self):
            return mi.ScalarBoundingBox3f()

        def to_string(self):
            return f"AcdfEnvmap[strategy={self.strategy}, bytes={self.bytes}]"

    class BatchedEnvmap(AcdfEnvmap):
        """Every strategy, in the scalar variants: each call one acdf call on a batch of one row (the JIT
        variants' acdf_envmap is NativeEnvmap)."""

        @property
        def bytes(self):
            """Of acdf's sampling tables, those built so far (a local light builds a normal cell's when
            a call first needs it)."""
            return self.light.bytes

        def _to_map(self, world_dirs):
            """Map-frame rows, and which of them are directions (an inactive lane's may not be)."""
            ok, rows = _usable(_rows(world_dirs))
            return ok, rows @ self.map_from_world.T

        def _normals(self, it):
            if not self.strategy.startswith("local"):
                return None
            n = _rows(it.n) @ self.map_from_world.T
            return n if np.all(np.isfinite(n)) and np.all(np.linalg.norm(n, axis=1) > 0.5) else None

        def _radiance(self, world_dirs):
            ok, dirs = self._to_map(world_dirs)
            return _color(mi, np.where(ok[:, None], self.light.eval(dirs), 0.0))

        def eval(self, si, active=True):
            return self._radiance(-si.wi)

        def eval_direction(self, it, ds, active=True):
            return self._radiance(ds.d)

        def _positions(self, it):
            """Map-frame points lit, where the light has portals and the interaction a position."""
            if not self.portals:
                return None
            p = _rows(it.p)
            # An inactive lane may hold anything; its results are not used.
            return np.where(np.isfinite(p).all(axis=1, keepdims=True), p, 0.0) @ self.map_from_world.T

        def pdf_direction(self, it, ds, active=True):
            ok, dirs = self._to_map(ds.d)
            pdf = self.light.pdf(dirs, normal=self._normals(it), position=self._positions(it),
                                 allow_incomplete_pdf=self.incomplete)
            return _float(mi, np.where(ok, pdf, 0.0))

        def sample_direction(self, it, sample, active=True):
            dirs, radiance, pdf = self.light.sample(_variates(sample), normal=self._normals(it),
                                                   position=self._positions(it), allow_incomplete_pdf=self.incomplete)
            world = dirs @ self.world_from_map.T
            p = _rows(it.p)
            # Beyond any scene: the shadow ray must reach past every occluder, and the scene's
            # bounds are not known here (set_scene is not called on Python emitters). 1e15 keeps
            # |p - ds.p|^2 finite in single precision and the direction exact to rounding.
            dist = np.full(len(pdf), _FAR)
            weight = np.where(pdf[:, None] > 0, radiance / np.where(pdf > 0, pdf, 1.0)[:, None], 0.0)
            ds = mi.DirectionSample3f()
            d = _vector(mi, world)
            ds.d = d
            ds.dist = _float(mi, dist)
            ds.p = _vector(mi, p + world * dist[:, None])
            ds.n = -d
            ds.pdf = _float(mi, pdf)
            ds.time = it.time
            ds.delta = False
            ds.emitter = self
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
        """JIT variants, every strategy: acdf's tables as arrays of the variant (a table of the pixels:
        a cascade, alias tables or a mip pyramid; one per normal cell over blocks of pixels: local; or
        none: uniform-sphere), sampled and evaluated by drjit operations that Mitsuba records into its
        kernels with the rest of the path (no Python or acdf call per wavefront).
        A local light samples each lane's normal cell's table, lanes without a normal its complete
        table, as acdf's EnvironmentLight does."""

        def _load(self, portals):
            AcdfEnvmap._load(self, portals)
            light = self.light
            width, height = light.map.width, light.map.height
            rgb = light.map.rgb.reshape(-1) * np.float32(self.scale)
            self.radiance = mi.Float(rgb.astype(np.float32))
            self.width, self.height = width, height
            self.cos_edge = mi.Float64(_pixel_solid_angles(width, height)[0])
            linear = np.eye(4)
            linear[:3, :3] = self.world_from_map
            self.to_world = mi.Transform4f(linear)
            self.to_map = mi.Transform4f(linear.T)  # a rotation's inverse: its transpose, exactly
            # Normals are mapped in double, as acdf's C++ maps them before finding their normal cell.
            self.normal_to_map = mi.Transform4d(linear.T)
            # local and local-compensated: the tables of calls with a normal; those without one (and
            # sample_ray) get the complete adaptive table, as acdf's EnvironmentLight does.
            local = light.local_arrays()
            self.local = None if local is None else _DrjitLocalTable(mi, local, width, height)
            if self.strategy == "uniform-sphere" or light.emits_nothing:
                self.table = self.complete = None
            else:
                self.table = _drjit_pixel_table(mi, light, self.incomplete)
                self.complete = (_drjit_pixel_table(mi, light, False)
                                 if self.incomplete and self.local is None else self.table)
            self.portals_seen = (_DrjitPortals(mi, light.portal_arrays(), self.world_from_map, self.incomplete)
                                 if self.portals and not light.emits_nothing else None)
            # Everything is in drjit arrays now: the C++ light (the map's pixels again, and every
            # table) would double the plugin's memory for nothing.
            self.bytes = light.bytes  # of acdf's sampling tables, all built for the export
            del self.light

        def _to_world(self, d):
            return self.to_world @ d

        def _to_map(self, d):
            return self.to_map @ d

        def _normal_cell(self, it, active):
            """The local table's normal cell of each lane's it.n, and which lanes have a normal (a
            default interaction's fields are empty; a medium interaction's normal is zero)."""
            if self.local is None or dr.width(it.n) == 0:
                return None, None
            normal = self.normal_to_map @ mi.Vector3d(it.n)
            has_normal = active & (dr.squared_norm(normal) > 0)
            return self.local.cell_of(normal), has_normal

        def _radiance_of_pixel(self, row, column, active):
            return dr.gather(mi.Color3f, self.radiance, row * self.width + column, active)

        def _radiance(self, world_dir, active):
            row, column = _pixel_of(mi, self._to_map(world_dir), self.width, self.height)
            return self._radiance_of_pixel(row, column, active)

        def _sample(self, table, u, active, cell=None, local=None):
            """Map-frame direction, its pixel and pdf per steradian (0 for a light that emits nothing):
            from `table`, and for the lanes `local` from the local table of their normal cell `cell`."""
            if self.strategy == "uniform-sphere":
                d = mi.warp.square_to_uniform_sphere(u)
                row, column = _pixel_of(mi, d, self.width, self.height)
                return d, row, column, mi.Float(dr.inv_four_pi)
            if table is None:
                zero = mi.UInt32(0)
                return mi.Vector3f(0, 0, 1), zero, zero, mi.Float(0)
            drawn = table.sample(u, active if cell is None else active & ~local)
            if cell is not None:
                # Each lane's own table: both are traced, each gathering for its own lanes only; the
                # direction is placed once, in the pixel drawn.
                drawn = (dr.select(local, a, b) for a, b in zip(self.local.sample(cell, u, local), drawn))
            row, column, down, right, pdf = drawn
            d = _direction_in_pixel(mi, self.cos_edge, self.width, row, column, down, right, active)
            return d, row, column, pdf

        def eval(self, si, active=True):
            return self._radiance(-si.wi, active)

        def eval_direction(self, it, ds, active=True):
            return self._radiance(ds.d, active)

        def _strategy_pdf(self, row, column, cell, local, active):
            """The strategy's density at a pixel: each lane's local table's (lanes `local`), else the table's."""
            if self.strategy == "uniform-sphere":
                return mi.Float(dr.inv_four_pi)
            if self.table is None:
                return mi.Float(0)
            if cell is None:
                return self.table.pdf(row, column, active)
            return dr.select(local, self.local.pdf(cell, row, column, local),
                             self.table.pdf(row, column, active & ~local))

        def _seen(self, it, active):
            """The portals as seen from each lane's it.p (None without portals or positions)."""
            if self.portals_seen is None or dr.width(it.p) == 0:
                return None
            return self.portals_seen.seen_from(it.p, active)

        def pdf_direction(self, it, ds, active=True):
            row, column = _pixel_of(mi, self._to_map(ds.d), self.width, self.height)
            pdf = self._strategy_pdf(row, column, *self._normal_cell(it, active), active)
            seen = self._seen(it, active)
            return pdf if seen is None else self.portals_seen.mixture_pdf(seen, ds.d, pdf)

        def sample_direction(self, it, sample, active=True):
            cell, local = self._normal_cell(it, active)
            seen = self._seen(it, active)
            if seen is None:
                d_map, row, column, pdf = self._sample(self.table, sample, active, cell, local)
                d = self._to_world(d_map)
            else:
                # The lanes that go through a portal, and the others' variate rescaled for the table.
                through, u = self.portals_seen.choose(seen, sample)
                d_map, row, column, pdf = self._sample(self.table, u, active & ~through, cell,
                                                       None if local is None else local & ~through)
                d = dr.select(through, self.portals_seen.sample(seen, sample, through), self._to_world(d_map))
                row_through, column_through = _pixel_of(mi, self._to_map(d), self.width, self.height)
                row, column = dr.select(through, row_through, row), dr.select(through, column_through, column)
                if self.portals_seen.share < 1.0:  # else mixture_pdf does not read it where through
                    pdf = dr.select(through, self._strategy_pdf(row, column, cell, local, active & through), pdf)
                pdf = self.portals_seen.mixture_pdf(seen, d, pdf)
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


# How far from a pixel's edges (a fraction of the pixel) NativeEnvmap places its samples: a float32
# direction's pixel, found again by pdf_direction, is then the pixel it was drawn in (float32 angles
# err by a few 1e-7 rad, 1e-3 of a pixel of a 8192 x 4096 map). The radiance and the pdf are
# constant on a pixel, so where in it a sample lies changes no estimate of the map's light; against
# a BRDF that varies inside a pixel, the shift is of order 1e-3 of the pixel's share of the light.
_PIXEL_MARGIN = 2e-3


def _pixel_of(mi, d, width, height):
    """The pixel (row, column) of a map-frame direction: theta from +Y, phi from -Z towards +X
    (acdf's lat-long mapping, envmap/lat_long.h), in the variant's float arithmetic."""
    theta = dr.atan2(dr.sqrt(d.x * d.x + d.z * d.z), d.y)
    phi = dr.atan2(d.x, -d.z)
    phi = dr.select(phi < 0, phi + dr.two_pi, phi)
    row = dr.minimum(mi.UInt32(dr.maximum(theta * (height * dr.inv_pi), 0)), height - 1)
    column = dr.minimum(mi.UInt32(dr.maximum(phi * (width * dr.inv_two_pi), 0)), width - 1)
    return row, column


class _DrjitCdfs:
    """One sampled axis of a cascade (Cascade.arrays, EnvironmentLight.cascade_arrays) in a JIT
    variant's arrays, held as acdf's Cascade holds it: each 1D CDF runs from value 0 at vertex 0 to
    value 1 at vertex `cells`, so only its interior breakpoints are kept, their vertices packed
    into the narrowest unsigned integers that hold them. CDF k's interval j has CDF first[k] + k + j
    of the next axis below it."""

    def __init__(self, mi, arrays, cells):
        start = np.asarray(arrays["start"], dtype=np.int64)
        inner = np.ones(len(arrays["vertex"]), dtype=bool)
        inner[start[:-1]] = inner[start[1:] - 1] = False
        self.mi = mi
        self.cells = cells
        # CDFs that all keep every vertex (a uniform level, e.g. acdf's pixel tables inside a block)
        # need neither offsets nor vertices: CDF k's interior breakpoint j lies at vertex j + 1, after
        # k (cells - 1) others, and a cell is its own interval.
        self.every_vertex = bool(np.all(np.diff(start) == cells + 1))
        # (One unused entry where no CDF has interior breakpoints: drjit gathers from no array.)
        value = np.asarray(arrays["value"], dtype=np.float32)[inner]
        self.value = mi.Float(value if len(value) else np.zeros(1, np.float32))
        self.first = self.vertex = None
        if not self.every_vertex:
            self.first = mi.UInt32(start - 2 * np.arange(len(start)))  # interior breakpoints before CDF k
            self.bits = 8 if cells <= 1 << 8 else 16 if cells <= 1 << 16 else 32
            per_word = 32 // self.bits
            vertex = np.zeros(max(-(-len(value) // per_word), 1) * per_word, dtype=f"<u{self.bits // 8}")
            vertex[:len(value)] = np.asarray(arrays["vertex"])[inner]
            self.vertex = mi.UInt32(np.frombuffer(vertex.tobytes(), dtype="<u4"))
        # Halvings that find a lane's interval in the longest CDF.
        self.steps = int(np.ceil(np.log2(np.diff(start).max() - 1)))

    @property
    def bytes(self):
        return 4 * sum(dr.width(a) for a in (self.first, self.value, self.vertex) if a is not None)

    def _value(self, k, active):
        return dr.gather(self.mi.Float, self.value, k, active)

    def _vertex(self, k, active):
        """The vertex of interior breakpoint k, unpacked."""
        mi = self.mi
        shift = {8: 2, 16: 1, 32: 0}[self.bits]
        word = dr.gather(mi.UInt32, self.vertex, k >> shift, active)
        return (word >> ((k & ((1 << shift) - 1)) * self.bits)) & ((1 << self.bits) - 1) if shift else word

    def _count_at_most(self, first, count, of, threshold, active):
        """How many of the `count` interior breakpoints from `first` have of(k) <= threshold (of:
        the values or the vertices, non-decreasing in a CDF): a binary search of the lane's own CDF."""
        at, left = first, count
        for _ in range(self.steps):
            half = left >> 1
            live = active & (left > 0)
            below = live & (of(at + half, live) <= threshold)
            at = dr.select(below, at + half + 1, at)
            left = dr.select(below, left - half - 1, half)
        return at - first

    def _interval(self, cdf, find, active, kind):
        """The interval j = find(first, count) of CDF `cdf` (whose interior breakpoints are the `count`
        from `first`), the next axis' CDF below it, its CDF values (lo, hi) in `kind` (mi.Float or
        mi.Float64) and vertices (a, b), and its density on the axis' unit interval: its mass spread
        over its cells."""
        mi = self.mi
        if self.every_vertex:
            first, count = cdf * (self.cells - 1), mi.UInt32(self.cells - 1)
        else:
            first = dr.gather(mi.UInt32, self.first, cdf, active)
            count = dr.gather(mi.UInt32, self.first, cdf + 1, active) - first
        j = find(first, count)
        starts, ends = active & (j > 0), active & (j < count)
        lo = dr.select(starts, kind(self._value(first + j - 1, starts)), 0)
        hi = dr.select(ends, kind(self._value(first + j, ends)), 1)
        if self.every_vertex:
            a, b = j, j + 1
        else:
            a = dr.select(starts, self._vertex(first + j - 1, starts), 0)
            b = dr.select(ends, self._vertex(first + j, ends), self.cells)
        return first + cdf + j, lo, hi, a, b, (hi - lo) * self.cells / kind(dr.maximum(b - a, 1))

    def draw(self, cdf, u, active, kind):
        """Variate u in [0, 1) through CDF `cdf`: the next axis' CDF below its interval (which has
        mass), the grid coordinate u maps to (in `kind`), the interval's vertices (a, b) and its
        density on the axis' unit interval."""
        child, lo, hi, a, b, density = self._interval(
            cdf, lambda first, count: self._count_at_most(first, count, self._value, u, active), active, kind)
        return child, kind(a) + (kind(u) - lo) / (hi - lo) * kind(b - a), a, b, density

    def lookup(self, cdf, cell, active, kind):
        """The next axis' CDF below the interval of CDF `cdf` that holds `cell`, and the density
        there on the axis' unit interval (in `kind`)."""
        def find(first, count):
            return cell if self.every_vertex else self._count_at_most(first, count, self._vertex, cell, active)

        child, _, _, _, _, density = self._interval(cdf, find, active, kind)
        return child, density


def _pixel_solid_angles(width, height):
    """cos theta at each map row's top edge (and the last row's bottom), and the solid angle of each
    row's pixels, as acdf's LatLongMapping has them (exact at the poles)."""
    cos_edge = np.cos(np.pi * np.arange(height + 1) / height)
    cos_edge[0], cos_edge[-1] = 1.0, -1.0
    return cos_edge, (cos_edge[:-1] - cos_edge[1:]) * (2 * np.pi / width)


def _direction_in_pixel(mi, cos_edge, width, row, column, down, right, active):
    """The map-frame direction at fractions (down, right) of pixel (row, column), uniform in solid
    angle inside it as acdf's (envmap/lat_long.h), kept _PIXEL_MARGIN from its edges. Placed in
    double: in float32, cos theta near a pole cannot tell a pixel's rows apart."""
    down = mi.Float64(dr.clip(down, _PIXEL_MARGIN, 1 - _PIXEL_MARGIN))
    right = mi.Float64(dr.clip(right, _PIXEL_MARGIN, 1 - _PIXEL_MARGIN))
    top, bottom = dr.gather(mi.Float64, cos_edge, row, active), dr.gather(mi.Float64, cos_edge, row + 1, active)
    cos_theta = top + down * (bottom - top)
    sin_theta = dr.sqrt(dr.maximum(0, (1 - cos_theta) * (1 + cos_theta)))
    sin_phi, cos_phi = dr.sincos((mi.Float64(column) + right) * (2 * np.pi / width))
    return mi.Vector3f(mi.Float(sin_theta * sin_phi), mi.Float(cos_theta), mi.Float(-sin_theta * cos_phi))


class _DrjitTable:
    """An acdf table of a map's pixels (a two-level cascade: rows, then the columns of each row
    interval) in a JIT variant's arrays. Its density on the unit square is that of acdf's
    EnvironmentTable; per steradian it is divided by W H times the pixel's solid angle, as acdf's
    (envmap/environment_table.h). sample() draws a pixel and where in it; _direction_in_pixel places
    the direction there."""

    def __init__(self, mi, levels, width, height):
        self.mi = mi
        self.rows = _DrjitCdfs(mi, levels[0], height)
        self.columns = _DrjitCdfs(mi, levels[1], width)
        self.width, self.height = width, height
        solid_angle = _pixel_solid_angles(width, height)[1]
        self.pdf_scale = mi.Float((1.0 / (float(width) * height * solid_angle)).astype(np.float32))

    def _density(self, row, row_density, column_density, active):
        return row_density * column_density * dr.gather(self.mi.Float, self.pdf_scale, row, active)

    def sample(self, u, active):
        """The pixel (row, column) drawn, where in it (down, right: fractions) and the pdf per steradian."""
        mi = self.mi
        below_one = float(np.nextafter(np.float32(1), np.float32(0)))
        u0, u1 = dr.clip(u.x, 0, below_one), dr.clip(u.y, 0, below_one)
        below, row_at, a, b, row_density = self.rows.draw(0, u0, active, mi.Float)
        row = dr.clip(mi.UInt32(row_at), a, b - 1)
        _, column_at, a, b, column_density = self.columns.draw(below, u1, active, mi.Float)
        column = dr.clip(mi.UInt32(column_at), a, b - 1)
        return (row, column, row_at - mi.Float(row), column_at - mi.Float(column),
                self._density(row, row_density, column_density, active))

    def pdf(self, row, column, active):
        """Density per steradian of sample() on map pixel (row, column)."""
        below, row_density = self.rows.lookup(0, row, active, self.mi.Float)
        column_density = self.columns.lookup(below, column, active, self.mi.Float)[1]
        return self._density(row, row_density, column_density, active)


class _DrjitPixelChoice:
    """What the alias and hierarchical tables share: they give a pixel's probability, which per steradian
    is P(pixel) W H times 1 / (W H x the row's pixel solid angle), in double as acdf's EnvironmentTable
    has it. pdf() answers it for map pixel (row, column) from the table's _probability (float64)."""

    def __init__(self, mi, width, height):
        self.mi = mi
        self.width, self.height = width, height
        self.pixels = float(width) * height
        self.pdf_scale = mi.Float64(1.0 / (self.pixels * _pixel_solid_angles(width, height)[1]))

    def pdf(self, row, column, active):
        """Density per steradian of sample() on map pixel (row, column)."""
        mi = self.mi
        density = self._probability(row, column, active) * self.pixels
        return mi.Float(density * dr.gather(mi.Float64, self.pdf_scale, row, active))


class _DrjitAliasTable(_DrjitPixelChoice):
    """An acdf alias table of a map's pixels (PixelAlias, envmap/pixel_alias.h;
    EnvironmentLight.alias_arrays) in a JIT variant's arrays: an alias table of the rows, then one of
    the row's columns, each variate split in double as acdf's AliasTable splits it, so that the same
    variates give the same pixel and the same position in it."""

    def __init__(self, mi, arrays, width, height):
        super().__init__(mi, width, height)
        kinds = {"acceptance": mi.Float, "alias": mi.UInt32, "probability": mi.Float}
        self.rows, self.columns = ({name: kind(arrays[level][name]) for name, kind in kinds.items()}
                                   for level in ("rows", "columns"))

    def _draw(self, table, first, slots, u, active):
        """Variate u (float32 in [0, 1)) through the alias table of `slots` slots from `first` in
        `table`: the cell drawn and u's fraction left, remapped to [0, 1) (float32)."""
        mi = self.mi
        scaled = mi.Float64(u) * slots
        slot = dr.minimum(mi.UInt32(scaled), slots - 1)
        fraction = scaled - mi.Float64(slot)
        acceptance = mi.Float64(dr.gather(mi.Float, table["acceptance"], first + slot, active))
        kept = fraction < acceptance
        cell = dr.select(kept, slot, dr.gather(mi.UInt32, table["alias"], first + slot, active))
        remapped = dr.select(kept, fraction / acceptance, (fraction - acceptance) / (1 - acceptance))
        return cell, dr.minimum(mi.Float(remapped), _below(1))

    def _probability(self, row, column, active):
        mi = self.mi
        row_probability = dr.gather(mi.Float, self.rows["probability"], row, active)
        column_probability = dr.gather(mi.Float, self.columns["probability"], row * self.width + column, active)
        return mi.Float64(row_probability) * mi.Float64(column_probability)

    def sample(self, u, active):
        """The pixel (row, column) drawn, where in it (down, right: fractions) and the pdf per steradian."""
        u0, u1 = _unit_variates(u)
        row, down = self._draw(self.rows, 0, self.height, u0, active)
        column, right = self._draw(self.columns, row * self.width, self.width, u1, active)
        return row, column, down, right, self.pdf(row, column, active)


class _DrjitHierarchicalTable(_DrjitPixelChoice):
    """An acdf hierarchical table of a map's pixels (HierarchicalWarp2D,
    sampling/hierarchical_warp_2d.h; EnvironmentLight.hierarchical_arrays) in a JIT variant's arrays:
    its mip pyramid descended from the top by splitting the variates, in double as acdf's C++
    descends it, so that the same variates give the same pixel and the same position in it."""

    def __init__(self, mi, levels, width, height):
        super().__init__(mi, width, height)
        blocks = [np.asarray(level["blocks"], dtype=np.float32) for level in levels]
        # Every level's blocks end to end, the pixels' first; per level the index of its first node
        # (of the level above) and the nodes per row there.
        self.blocks = mi.Float(np.concatenate(blocks))
        self.first_node = [int(n) for n in np.cumsum([0] + [len(b) // 4 for b in blocks[:-1]])]
        self.parent_columns = [int(level["parent_columns"]) for level in levels]

    def _children(self, level, row, column, active):
        """The masses (float64) of the four children on `level` of node (row, column) of the level above."""
        mi = self.mi
        node = self.first_node[level] + row * self.parent_columns[level] + column
        return [mi.Float64(dr.gather(mi.Float, self.blocks, 4 * node + k, active)) for k in range(4)]

    @staticmethod
    def _choose(u, first, second):
        """One binary choice of the descent (hierarchical_warp_2d.cpp's choose): whether u takes the
        second branch, and u rescaled to [0, 1) inside the branch taken."""
        total = first + second
        p = first / total
        taken = ~(u < p)
        u = dr.select(taken, (u - p) / (second / total), u / p)
        return taken, dr.minimum(u, float(np.nextafter(1.0, 0.0)))

    def _probability(self, row, column, active):
        node = (row >> 1) * self.parent_columns[0] + (column >> 1)
        slot = 4 * node + 2 * (row & 1) + (column & 1)
        return self.mi.Float64(dr.gather(self.mi.Float, self.blocks, slot, active))

    def sample(self, u, active):
        """The pixel (row, column) drawn, where in it (down, right: float64 fractions) and the pdf per
        steradian."""
        mi = self.mi
        u0, u1 = (mi.Float64(v) for v in _unit_variates(u))
        row = column = mi.UInt32(0)
        for level in reversed(range(len(self.parent_columns))):
            top_left, top_right, bottom_left, bottom_right = self._children(level, row, column, active)
            down, u0 = self._choose(u0, top_left + top_right, bottom_left + bottom_right)
            left_mass, right_mass = dr.select(down, bottom_left, top_left), dr.select(down, bottom_right, top_right)
            right, u1 = self._choose(u1, left_mass, right_mass)
            row = dr.select(down, 2 * row + 1, 2 * row)
            column = dr.select(right, 2 * column + 1, 2 * column)
        return row, column, u0, u1, self.pdf(row, column, active)


def _drjit_pixel_table(mi, light, allow_incomplete_pdf):
    """The drjit sampler of a light's table of pixels: its alias tables, its pyramid or its cascade."""
    width, height = light.map.width, light.map.height
    if light.strategy == "alias":
        return _DrjitAliasTable(mi, light.alias_arrays(), width, height)
    if light.strategy == "hierarchical":
        return _DrjitHierarchicalTable(mi, light.hierarchical_arrays(), width, height)
    return _DrjitTable(mi, light.cascade_arrays(allow_incomplete_pdf=allow_incomplete_pdf), width, height)


class _DrjitLocalTable:
    """An acdf LocalEnvironmentTable (envmap/local_environment_table.h; EnvironmentLight.local_arrays)
    in a JIT variant's arrays: per normal cell a cascade over the map's blocks of pixels, then the
    block's exact pixel table (_DrjitCdfs each), sampled as acdf's C++ samples them so that the same
    variates give the same pixel: each level drawn in double and placed as a float32 coordinate of its
    axis (GridAxis::place), the place inside the block's cell reused as the pixel table's variates."""

    def __init__(self, mi, arrays, width, height):
        self.mi = mi
        self.normal_rows, self.normal_columns = arrays["normal_rows"], arrays["normal_columns"]
        self.block_height, self.block_width = arrays["block_height"], arrays["block_width"]
        block_rows, self.block_columns = -(-height // self.block_height), -(-width // self.block_width)
        # Per level, its CDFs and its axis on the unit interval. The normal cells' block tables lie
        # end to end: CDF k of the block rows is normal cell k's.
        self.blocks = [(_DrjitCdfs(mi, level, cells), _DrjitAxis((0.0, 1.0), cells))
                       for level, cells in zip(arrays["blocks"], (block_rows, self.block_columns))]
        self.pixels = [(_DrjitCdfs(mi, level, cells), _DrjitAxis((0.0, 1.0), cells))
                       for level, cells in zip(arrays["pixels"], (self.block_height, self.block_width))]
        self.pixel_distributions = mi.UInt32(arrays["pixel_distributions"])
        self.width, self.height = width, height
        solid_angle = _pixel_solid_angles(width, height)[1]
        blocks = block_rows * self.block_columns
        self.pdf_scale = mi.Float64(1.0 / (float(blocks) * self.block_height * self.block_width * solid_angle))

    def cell_of(self, normal):
        """The normal cell of map-frame normals (float64, non-zero): as LocalEnvironmentTable::sliceOf,
        the pixel of a normal_columns x normal_rows lat-long grid, its last row and column taking
        theta = pi and phi rounded up to 2 pi."""
        row, column = _pixel_of(self.mi, normal, self.normal_columns, self.normal_rows)
        return row * self.normal_columns + column

    def _kind(self, cdfs):
        """The arithmetic a level is drawn and looked up in: float32 where each interval is one cell
        (no rounding can leave it), else double as in acdf's Cascade, so that the cell is acdf's."""
        return self.mi.Float if cdfs.every_vertex else self.mi.Float64

    def _draw(self, level, cdf, u, active):
        """Variate u through CDF `cdf` of a level, as acdf's Cascade::sampleCellsInSlice: the next
        level's CDF, the cell drawn, where inside it and the density (float64)."""
        mi = self.mi
        cdfs, axis = level
        kind = self._kind(cdfs)
        child, at, a, b, density = cdfs.draw(cdf, u, active, kind)
        if cdfs.every_vertex:
            return child, a, at - kind(a), mi.Float64(density)
        x = axis.place(mi, at, a, b)
        cell = axis.cell_of(mi, x)
        return child, cell, axis.grid_coordinate(mi, x) - mi.Float64(cell), density

    def _lookup(self, level, cdf, cell, active):
        """The next level's CDF below cell `cell` of CDF `cdf`, and the density there (float64)."""
        cdfs = level[0]
        child, density = cdfs.lookup(cdf, cell, active, self._kind(cdfs))
        return child, self.mi.Float64(density)

    def _density(self, row, block_density, pixel_density, active):
        scale = dr.gather(self.mi.Float64, self.pdf_scale, row, active)
        return self.mi.Float(block_density * pixel_density * scale)

    def _pixel_table(self, block_row, block_column, active):
        return dr.gather(self.mi.UInt32, self.pixel_distributions, block_row * self.block_columns + block_column,
                         active)

    def sample(self, cell, u, active):
        """For lanes of normal cell `cell`: the pixel (row, column) drawn, where in it (down, right:
        fractions, float32 as _DrjitTable's) and the pdf per steradian."""
        mi = self.mi
        u0, u1 = _unit_variates(u)
        below, block_row, down, row_density = self._draw(self.blocks[0], cell, u0, active)
        _, block_column, right, column_density = self._draw(self.blocks[1], below, u1, active)
        pixels = self._pixel_table(block_row, block_column, active)
        v0, v1 = (dr.clip(mi.Float(f), 0, _below(1)) for f in (down, right))
        below, row, down, pixel_row_density = self._draw(self.pixels[0], pixels, v0, active)
        _, column, right, pixel_column_density = self._draw(self.pixels[1], below, v1, active)
        row, column = block_row * self.block_height + row, block_column * self.block_width + column
        density = self._density(row, row_density * column_density, pixel_row_density * pixel_column_density, active)
        return row, column, mi.Float(down), mi.Float(right), density

    def pdf(self, cell, row, column, active):
        """Density per steradian of sample(cell, .) on map pixel (row, column)."""
        block_row, block_column = row // self.block_height, column // self.block_width
        below, row_density = self._lookup(self.blocks[0], cell, block_row, active)
        column_density = self._lookup(self.blocks[1], below, block_column, active)[1]
        pixels = self._pixel_table(block_row, block_column, active)
        below, pixel_row_density = self._lookup(self.pixels[0], pixels, row - block_row * self.block_height, active)
        pixel_column_density = self._lookup(self.pixels[1], below, column - block_column * self.block_width, active)[1]
        return self._density(row, row_density * column_density, pixel_row_density * pixel_column_density, active)


# acdf's margins and thresholds of the half-vector tables (brdf/tabulated_brdf_sampler.cpp,
# half_vector.h): how far inside its s cell a sample stays (a fraction of the cell), and the |wo.wh|
# below which a sample reports pdf() instead of the density along its path.
_HALF_VECTOR_CELL_MARGIN = 1e-6
_ROUND_TRIP_EXACT = 1e-3


def _find_openings(mi, scene):
    """acdf.find_openings on the scene's shapes from its first sensor; None where it cannot look: no
    perspective sensor, or a shape other than meshes (rectangles, cubes, OBJ and PLY files) and
    spheres, whose surfaces the search would miss."""
    sensors = scene.sensors()
    if not sensors or sensors[0].class_name() not in ("PerspectiveCamera", "ThinLensCamera"):
        return None
    meshes, spheres = [], []
    for shape in scene.shapes():
        if shape.is_mesh():
            meshes.append((np.asarray(shape.vertex_positions_buffer(), dtype=np.float64).reshape(-1, 3),
                           np.asarray(shape.faces_buffer(), dtype=np.int64).reshape(-1, 3)))
        elif shape.shape_type() == int(mi.ShapeType.Sphere):
            matrix = np.asarray(mi.traverse(shape)["to_world"].matrix, dtype=np.float64).reshape(4, 4)
            spheres.append([*matrix[:3, 3], np.linalg.norm(matrix[:3, 0])])
        else:
            return None
    sensor = sensors[0]
    params = mi.traverse(sensor)
    matrix = np.asarray(params["to_world"].matrix, dtype=np.float64).reshape(4, 4)
    width, height = (int(v) for v in sensor.film().size())
    # Mitsuba's x_fov is horizontal, acdf's camera's vertical; a mirrored frame sees the same points.
    x_fov = np.radians(float(np.asarray(params["x_fov"]).reshape(-1)[0]))
    fov = np.degrees(2 * np.arctan(np.tan(x_fov / 2) * height / width))
    eye = matrix[:3, 3]
    return acdf.find_openings(meshes, eye, eye + matrix[:3, 2], matrix[:3, 1], fov, width, height,
                              spheres=np.array(spheres).reshape(-1, 4))


def _portal_of(mi, name, shape):
    """A nested rectangle shape as an acdf portal (world frame). Mitsuba's rectangle spans [-1, 1]^2
    of its local z = 0 plane; its normal (+z) points to the side the light passes to, into the room."""
    if shape.shape_type() != int(mi.ShapeType.Rectangle):
        _refuse("acdf_envmap", f"portal {name}: must be a rectangle")
    transform = mi.traverse(shape)["to_world"]
    matrix = np.asarray(transform.matrix, dtype=np.float64).reshape(4, 4)
    normal = np.asarray(transform.inverse_transpose, dtype=np.float64).reshape(4, 4)[:3, 2]
    linear = matrix[:3, :3]
    portal = {"corner": matrix[:3, :3] @ [-1.0, -1.0, 0.0] + matrix[:3, 3],
              "edge_u": linear @ [2.0, 0.0, 0.0], "edge_v": linear @ [0.0, 2.0, 0.0]}
    if np.dot(np.cross(portal["edge_u"], portal["edge_v"]), normal) < 0:  # a mirroring to_world
        portal["edge_u"], portal["edge_v"] = portal["edge_v"], portal["edge_u"]
    problem = acdf.portal_problem(portal)
    if problem:
        _refuse("acdf_envmap", f"portal {name}: {problem}")
    return portal


def _dot(a, b):
    """a . b of float64 3-vectors in acdf's order (sphere.h's dot): dr.dot fuses multiply-adds."""
    return a.x * b.x + a.y * b.y + a.z * b.z


def _first_where(lo, hi, holds, steps, active):
    """The first index in [lo, hi] where holds(index, live) is true, else hi, for a predicate false
    then true: acdf's lo/hi bisection (windowed_table_2d.cpp) step for step, `steps` halvings deep
    (enough for the longest range), so that rounding that breaks the order gives acdf's index too."""
    for _ in range(steps):
        live = active & (lo < hi)
        mid = lo + ((hi - lo) >> 1)
        above = live & holds(mid, live)
        hi = dr.select(above, mid, hi)
        lo = dr.select(live & ~above, mid + 1, lo)
    return lo


def _pick(index, values):
    """values[index] per lane, for a few values (a select per value)."""
    out = values[0]
    for i, value in enumerate(values[1:], 1):
        out = dr.select(index == i, value, out)
    return out


def _inside(x, lo, hi):
    """acdf's inside() (windowed_table_2d.cpp): x moved strictly inside [lo, hi] by 1e-9 of the
    square, or a quarter of a narrower interval."""
    margin = dr.minimum(1e-9, 0.25 * (hi - lo))
    return dr.clip(x, lo + margin, hi - margin)


class _DrjitWindowedTables:
    """acdf's WindowedTable2D (sampling/windowed_table_2d.h) of every portal, from
    EnvironmentLight.portal_arrays, in a JIT variant's arrays: the tables' float64 arrays end to end
    in one array, their fine-to-coarse lookups in another. A table is a layout: the offsets of its
    arrays and its sizes, Python ints for one table, per-lane UInt32 for each lane's own (the portal
    it chose). The functions are the C++ ones, term for term in double."""

    _VALUES = ("column_vertices", "row_vertices", "density", "summed_area", "row_integral")
    _CELLS = ("coarse_column_of_fine", "coarse_row_of_fine")

    def __init__(self, mi, portals):
        self.mi = mi
        values, cells, self.layouts = [], [], []
        for portal in portals:
            layout = {"columns": len(portal["column_vertices"]) - 1, "rows": len(portal["row_vertices"]) - 1,
                      "fine_columns": len(portal["coarse_column_of_fine"]),
                      "fine_rows": len(portal["coarse_row_of_fine"])}
            for names, arrays in ((self._VALUES, values), (self._CELLS, cells)):
                for name in names:
                    layout[name] = sum(len(a) for a in arrays)
                    arrays.append(np.asarray(portal[name]))
            self.layouts.append(layout)
        self.values = mi.Float64(np.concatenate(values).astype(np.float64))
        self.cells = mi.UInt32(np.concatenate(cells).astype(np.uint32))
        # Halvings that bisect the longest range of rows or columns.
        self.steps = (max(max(t["rows"], t["columns"]) for t in self.layouts) - 1).bit_length()

    def layout_of(self, chosen):
        """Each lane's table: table chosen[lane]."""
        if len(self.layouts) == 1:
            return self.layouts[0]
        return {key: _pick(chosen, [self.mi.UInt32(t[key]) for t in self.layouts]) for key in self.layouts[0]}

    def _value(self, at, active):
        return dr.gather(self.mi.Float64, self.values, at, active)

    def coarse_of(self, t, x, axis, active):
        """The coarse cell of coordinate x along axis "column" or "row" (columnOf, rowOf): through its
        fine cell, clamped into the square."""
        fine = self.mi.Float64(t[f"fine_{axis}s"])
        cell = self.mi.UInt32(dr.clip(dr.floor(x * fine), 0, fine - 1.0))
        return dr.gather(self.mi.UInt32, self.cells, t[f"coarse_{axis}_of_fine"] + cell, active)

    def coarse_of_end(self, t, x, axis, active):
        """The cell a window ending at x ends in: the one below a vertex it ends on (columnOfEnd, rowOfEnd)."""
        cell = self.coarse_of(t, x, axis, active)
        back = active & (cell > 0)
        back &= x <= self._value(t[f"{axis}_vertices"] + cell, back)
        return dr.select(back, cell - 1, cell)

    def along_row(self, t, row, a, column, active):
        """alongRow: the integral over [0, a] of row `row`'s density, a in column `column`."""
        start = self._value(t["row_integral"] + row * (t["columns"] + 1) + column, active)
        density = self._value(t["density"] + row * t["columns"] + column, active)
        return start + density * (a - self._value(t["column_vertices"] + column, active))

    def below_row(self, t, row, a, column, active):
        """belowRow: the integral over [0, a] x [0, B_row], linear in a inside column `column`."""
        at = t["summed_area"] + row * (t["columns"] + 1) + column
        lo, hi = self._value(at, active), self._value(at + 1, active)
        left = self._value(t["column_vertices"] + column, active)
        right = self._value(t["column_vertices"] + column + 1, active)
        return lo + (hi - lo) * ((a - left) / (right - left))

    def density(self, t, a, b, active):
        """The coarse cell's density at (a, b)."""
        cell = self.coarse_of(t, b, "row", active) * t["columns"] + self.coarse_of(t, a, "column", active)
        return self._value(t["density"] + cell, active)

    def mass(self, t, window, active):
        """WindowedTable2D::mass: the first and last coarse rows the window cuts from their running
        integrals along a, the whole rows between from the summed-area table."""
        a0, a1, b0, b1 = window
        active = active & (a1 > a0) & (b1 > b0)
        cut = _WindowCut(self, t, window, active)
        one_row = cut.J0 == cut.J1
        rows = active & ~one_row
        strips = cut.strip(cut.J1, rows) - cut.strip(cut.J0 + 1, rows)
        several = ((self._value(t["row_vertices"] + cut.J0 + 1, rows) - b0) * cut.across(cut.J0, rows) + strips
                   + (b1 - self._value(t["row_vertices"] + cut.J1, rows)) * cut.across(cut.J1, rows))
        mass = dr.select(one_row, (b1 - b0) * cut.across(cut.J0, active & one_row), several)
        return dr.select(active, dr.maximum(0.0, mass), 0.0)

    def sample(self, t, window, mass, u0, u1, active):
        """WindowedTable2D::sample's point (a, b) of the window (mass: its mass > 0): the row by u1
        over the window's running mass at the row vertices, the nearest row with mass where rounding
        picked one without, then the column by u0 over the row's running integral, stepping back
        over columns of no density; the middle of the window where it has no mass at all."""
        mi = self.mi
        a0, a1, b0, b1 = window
        cut = _WindowCut(self, t, window, active)
        J0, J1, columns = cut.J0, cut.J1, t["columns"]
        target = dr.clip(u1, 0.0, 1.0) * mass
        rows = active & (J1 > J0)
        first = (self._value(t["row_vertices"] + J0 + 1, rows) - b0) * cut.across(J0, rows)
        searching = rows & ~(target < first)
        base = cut.strip(J0 + 1, searching)

        def mass_at(vertex, live):
            return first + cut.strip(vertex, live) - base

        J = _first_where(J0 + 1, J1, lambda mid, live: mass_at(mid + 1, live) > target, self.steps, searching)
        J = dr.select(searching, J, J0)
        below = dr.select(searching, mass_at(J, searching), 0.0)
        across = cut.across(J, active)
        # A row of no mass in the window won by an ulp: the nearest row with mass (below first) instead.
        replaced = active & ~(across > 0)

        def has_mass(row, live):
            return live & (cut.across(row, live) > 0)

        def next_row(k, taken, seeking):
            lower = has_mass(J - k, seeking & (J >= J0 + k))
            upper = has_mass(J + k, seeking & ~lower & (J + k <= J1))
            taken = dr.select(lower, J - k, dr.select(upper, J + k, taken))
            seeking &= ~lower & ~upper
            return k + 1, taken, seeking & (k + 1 <= J1 - J0)

        _, taken, _ = dr.while_loop((mi.UInt32(1), J, replaced & (J1 > J0)), lambda k, taken, seeking: seeking,
                                    next_row)
        empty = replaced & (taken == J)  # no row has mass: `mass` was rounding
        J = taken
        row_lo = dr.maximum(self._value(t["row_vertices"] + J, active), b0)
        row_hi = dr.minimum(self._value(t["row_vertices"] + J + 1, active), b1)
        b = dr.select(replaced, 0.5 * (row_lo + row_hi), _inside(row_lo + (target - below) / across, row_lo, row_hi))

        running = t["row_integral"] + J * (columns + 1)
        start, end = self.along_row(t, J, a0, cut.I0, active), self.along_row(t, J, a1, cut.I1, active)
        along = start + dr.clip(u0, 0.0, 1.0) * (end - start)
        I = _first_where(cut.I0, cut.I1, lambda mid, live: self._value(running + mid + 1, live) > along, self.steps,
                         active)

        def no_density(column, live):
            return live & ~(self._value(t["density"] + J * columns + column, live) > 0)

        # `along` rounded to the row's end: the last column with mass.
        (I,) = dr.while_loop((I,), lambda column: no_density(column, active & (column > cut.I0)),
                             lambda column: (column - 1,))
        column_lo = dr.maximum(self._value(t["column_vertices"] + I, active), a0)
        column_hi = dr.minimum(self._value(t["column_vertices"] + I + 1, active), a1)
        density = self._value(t["density"] + J * columns + I, active)
        a = _inside(column_lo + (along - dr.maximum(self._value(running + I, active), start)) / density, column_lo,
                    column_hi)
        return dr.select(empty, 0.5 * (a0 + a1), a), dr.select(empty, 0.5 * (b0 + b1), b)


class _WindowCut:
    """A window of a table (per lane) as mass() and sample() both walk it: the coarse columns and rows
    at its ends (I0, I1, J0, J1), a row's integral across it and the strip below a row vertex."""

    def __init__(self, tables, t, window, active):
        self.tables, self.t, self.window = tables, t, window
        a0, a1, b0, b1 = window
        self.I0, self.I1 = tables.coarse_of(t, a0, "column", active), tables.coarse_of_end(t, a1, "column", active)
        self.J0, self.J1 = tables.coarse_of(t, b0, "row", active), tables.coarse_of_end(t, b1, "row", active)

    def across(self, row, active):
        a0, a1 = self.window[:2]
        return (self.tables.along_row(self.t, row, a1, self.I1, active)
                - self.tables.along_row(self.t, row, a0, self.I0, active))

    def strip(self, vertex, active):
        a0, a1 = self.window[:2]
        return (self.tables.below_row(self.t, vertex, a1, self.I1, active)
                - self.tables.below_row(self.t, vertex, a0, self.I0, active))


class _PortalsSeen:
    """What the portals are from each lane's point: every portal's window of its square and the map's
    light through it (its power, 0 where the lane is not on its inner side or the window holds too
    little: acdf's PortalTable::View), their sum, and the lanes that see one."""

    def __init__(self, windows, powers, active):
        self.windows = windows
        self.powers = powers
        self.total = sum(powers[1:], powers[0])
        self.lanes = active & (self.total > 0)


class _DrjitPortals:
    """acdf's portals (acdf.EnvironmentLight, envmap/environment_light.h, portal_table.h) in drjit, in
    float64 as acdf's C++, from the light's own tables (portal_arrays): from a point on a portal's
    inner side, a share of the samples goes through the portals seen, a portal chosen by its share
    of the map's light through them, the direction by the map's luminance through it (its
    WindowedTable2D sampled inside the window the portal covers from the point); pdf_direction is
    the mixture. Portals are few: every loop over them is unrolled into the kernel."""

    def __init__(self, mi, portals, world_from_map, allow_incomplete_pdf):
        """portals: the light's portal_arrays(), in the map frame, where acdf's light works;
        world_from_map: the plugin's rotation; allow_incomplete_pdf: as the plugin's calls to acdf
        (the portals' share of the samples depends on it). Points and directions are turned into
        the map frame in double, as acdf's callers turn them: a sample is a steep function of its
        window, which the float32 rotation's rounding (1e-7) would move by up to 1e-5 rad."""
        self.mi = mi
        self.share = acdf.EnvironmentLight.portal_share(allow_incomplete_pdf)
        rotated = not np.array_equal(world_from_map, np.eye(3))
        self.world_from_map = world_from_map if rotated else None
        self.map_from_world = world_from_map.T if rotated else None
        self.tables = _DrjitWindowedTables(mi, portals)
        self.portals = []
        for portal in portals:
            frame = {key: mi.Vector3d(*(float(c) for c in portal[key]))
                     for key in ("corner", "axis_u", "axis_v", "normal")}
            self.portals.append({**frame, **{key: float(portal[key]) for key in ("length_u", "length_v", "min_power")}})

    def _view(self, portal, layout, origin, active):
        """PortalTable::viewFrom: the window of the square the portal covers from origin, and its mass
        (0 behind the portal, in its plane, or below min_power)."""
        to_corner = portal["corner"] - origin
        h = -_dot(to_corner, portal["normal"])
        active = active & (h > 0)
        u0, v0 = _dot(to_corner, portal["axis_u"]), _dot(to_corner, portal["axis_v"])

        def coordinate(d):
            return 0.5 * (1.0 + d / dr.sqrt(d * d + h * h))

        window = (coordinate(u0), coordinate(u0 + portal["length_u"]), coordinate(v0),
                  coordinate(v0 + portal["length_v"]))
        power = self.tables.mass(layout, window, active)
        return window, dr.select(active & (power > portal["min_power"]), power, 0.0)

    def _turn(self, matrix, v):
        """The float64 vector v by a 3 x 3 matrix (None: the identity), row by row in acdf's dot order."""
        if matrix is None:
            return v
        return self.mi.Vector3d(*(float(m[0]) * v.x + float(m[1]) * v.y + float(m[2]) * v.z for m in matrix))

    def seen_from(self, p, active):
        origin = self._turn(self.map_from_world, self.mi.Vector3d(p))
        views = [self._view(portal, layout, origin, active)
                 for portal, layout in zip(self.portals, self.tables.layouts)]
        return _PortalsSeen([window for window, _ in views], [power for _, power in views], active)

    def choose(self, seen, sample):
        """The lanes whose sample goes through a portal (u0 below the share), and every lane's variates
        for the table: u0 rescaled where the lane sees a portal, as acdf's rescaledVariate."""
        u0 = self.mi.Float64(dr.clip(sample.x, 0.0, _ONE_MINUS_EPSILON))
        through = seen.lanes & (u0 < self.share)
        if self.share == 1.0:  # every lane that sees a portal goes through one
            return through, sample
        rescaled = self.mi.Float(dr.minimum((u0 - self.share) / (1 - self.share), _ONE_MINUS_EPSILON))
        return through, self.mi.Point2f(dr.select(seen.lanes, rescaled, sample.x), sample.y)

    def sample(self, seen, sample, active):
        """World directions through the portal each lane's u0 chooses by its share of the power (the
        last one seen takes what rounding leaves over), drawn by its table inside its window
        (PortalTable::sample: WindowedTable2D::sample, then directionAt)."""
        mi = self.mi
        at = mi.Float64(dr.clip(sample.x, 0.0, _ONE_MINUS_EPSILON)) / self.share * seen.total
        chosen, power, done = mi.UInt32(0), mi.Float64(0), mi.Bool(False)
        for i, next_power in enumerate(seen.powers):
            take = ~done & (next_power > 0)
            at = dr.select(take, at - power, at)
            chosen = dr.select(take, i, chosen)
            power = dr.select(take, next_power, power)
            done |= take & (at < next_power)
        window = tuple(_pick(chosen, list(bounds)) for bounds in zip(*seen.windows))
        a, b = self.tables.sample(self.tables.layout_of(chosen), window, power, dr.clip(at / power, 0.0, 1.0),
                                  mi.Float64(dr.clip(sample.y, 0.0, _ONE_MINUS_EPSILON)), active)
        # directionAt: s / sqrt(1 - s^2) with 1 +- s from a and 1 - a, exact near either end.
        x = (2.0 * a - 1.0) / (2.0 * dr.sqrt(a * (1.0 - a)))
        y = (2.0 * b - 1.0) / (2.0 * dr.sqrt(b * (1.0 - b)))
        axis_u, axis_v, normal = (_pick(chosen, [portal[key] for portal in self.portals])
                                  for key in ("axis_u", "axis_v", "normal"))
        w = axis_u * x + axis_v * y - normal
        return mi.Vector3f(self._turn(self.world_from_map, w * (1.0 / dr.sqrt(_dot(w, w)))))

    def _density_through(self, portal, layout, window, w, active):
        """PortalTable::densityThrough: the table's function per steradian at the unit direction w, 0
        for one not leaving through the portal's plane or outside the window."""
        du, dv, dn = _dot(w, portal["axis_u"]), _dot(w, portal["axis_v"]), -_dot(w, portal["normal"])
        qu, qv = dr.sqrt(du * du + dn * dn), dr.sqrt(dv * dv + dn * dn)
        a, b = 0.5 * (1.0 + du / qu), 0.5 * (1.0 + dv / qv)
        jacobian = 4.0 * (qu * qu * qu) * (qv * qv * qv) / (dn * dn * dn)
        a0, a1, b0, b1 = window
        active = active & (dn > 0) & ~((a < a0) | (a > a1) | (b < b0) | (b > b1))
        return dr.select(active, self.tables.density(layout, a, b, active) / jacobian, 0.0)

    def mixture_pdf(self, seen, w, strategy_pdf):
        """Where a lane sees a portal: the share times the seen portals' densities per steradian at w
        over their total power, plus the rest times the strategy's pdf (EnvironmentLight::mixturePdf);
        elsewhere the strategy's."""
        w = self._turn(self.map_from_world, self.mi.Vector3d(w))
        through = self.mi.Float64(0)
        for portal, layout, window, power in zip(self.portals, self.tables.layouts, seen.windows, seen.powers):
            through += self._density_through(portal, layout, window, w, seen.lanes & (power > 0))
        mixture = self.share * (through / seen.total)
        if self.share < 1.0:
            mixture += (1 - self.share) * self.mi.Float64(strategy_pdf)
        return dr.select(seen.lanes, self.mi.Float(mixture), strategy_pdf)


def _polar_angle(d):
    return dr.atan2(dr.sqrt(d.x * d.x + d.y * d.y), d.z)


def _azimuth(d):
    """In [0, 2 pi)."""
    phi = dr.atan2(d.y, d.x)
    return dr.select(phi < 0, phi + 2 * np.pi, phi)


def _cosine_hemisphere(mi, u0, u1):
    """acdf's cosine-weighted direction (sampling/sphere.h), in float64."""
    r2 = dr.minimum(u0, 1 - 2.0**-40)
    r = dr.sqrt(r2)
    sin_phi, cos_phi = dr.sincos(2 * np.pi * u1)
    return mi.Vector3d(r * cos_phi, r * sin_phi, dr.sqrt(1 - r2))


def _cosine_pdf(z):
    return dr.select(z > 0, z * (1 / np.pi), 0)


def _unit_variates(u):
    """A Point2f's coordinates clamped into [0, 1) (clampUnit)."""
    return dr.clip(u.x, 0, _below(1)), dr.clip(u.y, 0, _below(1))


def _cosine_sample(mi, u0, u1):
    """acdf's cosine-weighted sampler (CosineBrdfSampler): a direction and its pdf, in float64."""
    wi = _cosine_hemisphere(mi, mi.Float64(u0), mi.Float64(u1))
    return wi, _cosine_pdf(wi.z)


def _below(x):
    """The float32 just below x."""
    return float(np.nextafter(np.float32(x), np.float32(-np.inf)))


class _DrjitAxis:
    """An axis of a half-vector table as acdf's GridAxis (sampling/grid_axis.h) maps it: float32
    coordinates on `cells` cells of [lo, hi), their cells found in double."""

    def __init__(self, domain, cells):
        self.lo, self.hi = float(domain[0]), float(domain[1])
        self.cells = cells
        self.width = (self.hi - self.lo) / cells  # GridAxis::cellWidth, of the float32 bounds
        # The extreme coordinates place() returns, a 2^-24 fraction of a cell inside the domain.
        lo, hi, margin = np.float32(self.lo), np.float32(self.hi), self.width * 2.0**-24
        self.inner_lo = float(max(np.nextafter(lo, hi), np.float32(self.lo + margin)))
        self.inner_hi = float(min(np.nextafter(hi, lo), np.float32(self.hi - margin)))

    def grid_coordinate(self, mi, x):
        return (mi.Float64(x) - self.lo) * (1 / self.width)

    def cell_of(self, mi, x):
        """The cell of float32 coordinate x, clamped into the axis (GridAxis::cellOf)."""
        return dr.minimum(mi.UInt32(dr.maximum(self.grid_coordinate(mi, x), 0)), self.cells - 1)

    def cell(self, mi, angle):
        """The cell of a float64 angle: rounded to float32 and kept inside [lo, hi) first (onAxis,
        brdf/outgoing_cells.h)."""
        return self.cell_of(mi, dr.clip(mi.Float(angle), self.lo, _below(self.hi)))

    def place(self, mi, at, first, end):
        """The float32 coordinate of grid coordinate `at` (float64) in cells [first, end), inside the
        domain by a margin and moved by one float where rounding carried it across the range's
        edge (GridAxis::place). lo >= 0."""
        x = dr.clip(mi.Float(self.lo + at * self.width), self.inner_lo, self.inner_hi)
        cell = self.cell_of(mi, x)
        bits = dr.reinterpret_array(mi.UInt32, x)
        bits = dr.select(cell < first, bits + 1, dr.select(cell >= end, bits - 1, bits))
        return dr.reinterpret_array(mi.Float, bits)


def _half_vector(wo, wi, active):
    """The half vector of a reflection (upper hemisphere), |wo . h| and the lanes where both exist."""
    h = wi + wo
    length = dr.norm(h)
    h = h / length
    h = dr.select(h.z < 0, -h, h)
    cos_out = dr.abs(dr.dot(wo, h))
    return h, cos_out, active & (length > 0) & (cos_out > 0) & (h.z > 0)


class _DrjitHalfVectorTable:
    """An acdf.TabulatedBrdfSampler's table (brdf/tabulated_brdf_sampler.h) in a JIT variant's arrays,
    sampled and evaluated as its C++ sampler does: omega_o's slice of the outgoing cells, a cascade
    over the half vector's s = sqrt(theta_h / (pi/2)) and azimuth (phi_h, or relative to phi_o,
    folded when mirrored), uniform in solid angle inside a cell, reflected, mixed with cosine-weighted
    sampling. Directions and densities in float64 as in C++: a sample's half vector found again from
    omega_i then lies in its cell (the margin is 1e-6 of a cell), so pdf() answers its density."""

    def __init__(self, mi, sampler):
        table, options = sampler.table, sampler.table_options
        self.mi = mi
        self.cosine_weight = float(options["cosine_weight"])
        self.relative = options["layout"] == "isotropic"
        self.mirrored = self.relative and options["mirror"] == "true"
        k = table.conditioning_dims
        domains, shape = table.domains, table.shape
        self.outgoing = [_DrjitAxis(domains[d], shape[d]) for d in range(k)]
        self.s_axis = _DrjitAxis(domains[k], shape[k])
        self.azimuth = _DrjitAxis(domains[k + 1], shape[k + 1])
        levels = table.arrays()
        self.s = _DrjitCdfs(mi, levels[0], shape[k])
        self.phi = _DrjitCdfs(mi, levels[1], shape[k + 1])
        self.distributions = mi.UInt32(table.distributions)
        # 1 - cos theta_h at the s cells' edges, without cancellation near the pole.
        theta = (np.arange(shape[k] + 1) / shape[k]) ** 2 * (np.pi / 2)
        self.caps = mi.Float64(2 * np.sin(0.5 * theta) ** 2)

    @property
    def bytes(self):
        """Of its arrays."""
        return self.s.bytes + self.phi.bytes + 4 * dr.width(self.distributions) + 8 * dr.width(self.caps)

    def _distribution(self, wo, active):
        """The first-level CDF of omega_o's slice (OutgoingCells)."""
        mi = self.mi
        slice_ = self.outgoing[0].cell(mi, _polar_angle(wo))
        if len(self.outgoing) == 2:
            slice_ = slice_ * self.outgoing[1].cells + self.outgoing[1].cell(mi, _azimuth(wo))
        return dr.gather(mi.UInt32, self.distributions, slice_, active)

    def _per_steradian(self, density, cell, active):
        """The cascade's density (per unit s and azimuth) on s cell `cell` per steradian of omega_h,
        clamped into float32's positive range as acdf's Cascade does."""
        mi = self.mi
        density = mi.Float64(mi.Float(dr.clip(density, float(np.finfo(np.float32).smallest_subnormal),
                                              float(np.finfo(np.float32).max))))
        caps = dr.gather(mi.Float64, self.caps, cell + 1, active) - dr.gather(mi.Float64, self.caps, cell, active)
        return density * ((0.5 if self.mirrored else 1.0) * self.s_axis.width) / caps

    def pdf(self, wo, wi, active):
        """Density of omega_i (float64 unit vectors) given omega_o above the horizon, per steradian."""
        mi = self.mi
        w = self.cosine_weight
        h, cos_out, valid = _half_vector(wo, wi, active)
        cells = self.s_axis.cells
        s_cell = mi.UInt32(dr.minimum(dr.sqrt(_polar_angle(h) / (np.pi / 2)) * cells, cells - 1))
        phi = _azimuth(h)
        if self.relative:
            phi = phi - _azimuth(wo)
            phi = dr.select(phi < 0, phi + 2 * np.pi, phi)
            if self.mirrored:
                phi = dr.select(phi > np.pi, 2 * np.pi - phi, phi)
        below, s_density = self.s.lookup(self._distribution(wo, valid), s_cell, valid, mi.Float64)
        phi_density = self.phi.lookup(below, self.azimuth.cell(mi, phi), valid, mi.Float64)[1]
        density = s_density * phi_density / (self.azimuth.hi - self.azimuth.lo)
        table = self._per_steradian(density, s_cell, valid) / (4 * cos_out)
        has_mass = valid & (s_density > 0) & (phi_density > 0)
        return w * _cosine_pdf(wi.z) + dr.select(has_mass, (1 - w) * table, 0)

    def sample(self, wo, u, active):
        """omega_i and its density for omega_o (float64, above the horizon) and variates u (Point2f)."""
        mi = self.mi
        w = self.cosine_weight
        u0, u1 = _unit_variates(u)
        if w == 1:
            return _cosine_sample(mi, u0, u1)
        cosine = u0 < w
        drawn = active & ~cosine
        # The rest of u0's range drives the table; a mirrored table's u1 halves choose the sign of
        # the relative azimuth.
        v0 = dr.clip(mi.Float((mi.Float64(u0) - w) / (1 - w)), 0, _below(1))
        negative = (u1 >= 0.5) if self.mirrored else mi.Bool(False)
        v1 = dr.select(negative, 2 * u1 - 1, 2 * u1) if self.mirrored else u1
        below, s_at, a, b, s_density = self.s.draw(self._distribution(wo, drawn), v0, drawn, mi.Float64)
        # acdf places s as a float32 coordinate, then takes its cell and the fraction inside it.
        s_x = self.s_axis.place(mi, s_at, a, b)
        cell = self.s_axis.cell_of(mi, s_x)
        inside = dr.clip(self.s_axis.grid_coordinate(mi, s_x) - mi.Float64(cell),
                         _HALF_VECTOR_CELL_MARGIN, 1 - _HALF_VECTOR_CELL_MARGIN)
        _, phi_at, a, b, phi_density = self.phi.draw(below, v1, drawn, mi.Float64)
        phi = mi.Float64(self.azimuth.place(mi, phi_at, a, b))
        density = s_density * phi_density / (self.azimuth.hi - self.azimuth.lo)

        low, high = dr.gather(mi.Float64, self.caps, cell, drawn), dr.gather(mi.Float64, self.caps, cell + 1, drawn)
        cap = low + inside * (high - low)  # 1 - cos theta_h: uniform in solid angle inside the cell
        sin_theta = dr.sqrt(cap * (2 - cap))
        if self.relative:
            phi = _azimuth(wo) + dr.select(negative, -phi, phi)
        sin_phi, cos_phi = dr.sincos(phi)
        wh = mi.Vector3d(sin_theta * cos_phi, sin_theta * sin_phi, 1 - cap)
        cos_out = dr.dot(wo, wh)
        wi = wh * (2 * cos_out) - wo
        cos_out = dr.abs(cos_out)
        along_path = w * _cosine_pdf(wi.z) + (1 - w) * self._per_steradian(density, cell, drawn) / (4 * cos_out)

        if w > 0:
            wi = dr.select(cosine, _cosine_hemisphere(mi, mi.Float64(u0) / w, mi.Float64(u1)), wi)
        # Where omega_i does not determine omega_h well (and on the cosine side) acdf reports pdf().
        again = active & (cosine | (cos_out < _ROUND_TRIP_EXACT))
        found = self.pdf(wo, wi, again)
        return wi, dr.select(again & (cosine | (found > 0)), found, along_path)


def _clamp_density(mi, density):
    """A float64 density as the float32 acdf returns (clampDensity, sampling/sample.h): 0 where not
    positive, else held inside float32's positive finite range."""
    finfo = np.finfo(np.float32)
    clamped = mi.Float(dr.clip(density, float(finfo.smallest_subnormal), float(finfo.max)))
    return dr.select(density > 0, clamped, 0)


def _next_float_up(mi, x):
    """The float32 just above x, for x >= 0 (std::nextafter(x, 1.0f))."""
    return dr.reinterpret_array(mi.Float, dr.reinterpret_array(mi.UInt32, x) + 1)


def _sample_linear_segment(f, a, b):
    """acdf's sampleLinearSegment (sampling/linear_segment.h), in float64: the t in [0, 1] whose
    share of the linear density from a to b is f, by the cancellation-free root."""
    positive = f > 0  # false for NaN, which gives 0 as in C++
    f = dr.minimum(f, 1)
    scale = dr.maximum(a, b)
    a, b = a / scale, b / scale
    t = dr.minimum(f * (a + b) / (a + dr.sqrt((1 - f) * a * a + f * b * b)), 1)
    return dr.select(positive, dr.select(scale > 0, t, f), 0)


def _linear_segment_cdf(t, a, b):
    """acdf's linearSegmentCdf, the inverse of _sample_linear_segment, in float64."""
    positive = t > 0  # false for NaN, which gives 0 as in C++
    t = dr.minimum(t, 1)
    total = a + b
    cdf = dr.minimum(t * (2 * a * (1 - t) + total * t) / total, 1)
    return dr.select(positive, dr.select(total > 0, cdf, t), 0)


def _find_interval(mi, size, target, value):
    """The largest i in [0, size - 2] with value(i) <= target, for value non-decreasing in i with
    value(0) <= target (findInterval, bilinear_2d.cpp): a binary search of fixed depth."""
    lo, hi = mi.UInt32(0), mi.UInt32(size - 1)
    for _ in range(int(np.ceil(np.log2(max(size - 1, 1))))):
        mid = lo + (hi - lo) // 2
        searching = hi - lo > 1
        below = value(mid) <= target
        lo = dr.select(searching & below, mid, lo)
        hi = dr.select(searching & ~below, mid, hi)
    return lo


class _DrjitStrip:
    """Bilinear2D::Strip: the conditional over columns on the line at fraction `down` of row strip
    `row`, blended over the corners' slices, in float64 and in the C++ order of its sums."""

    def __init__(self, warp, corners, row, down, active):
        self.warp, self.active = warp, active
        gather = warp.gather
        rows, columns = warp.rows, warp.columns
        self.lines = []  # per corner: the offsets of vertex rows row and row + 1, and their weights
        for slice_, weight in corners:
            line0 = (slice_ * rows + row) * columns
            near, far = weight * (1 - down), weight * down
            cdf_near = near * gather(warp.row_mass, slice_ * rows + row, active)
            cdf_far = far * gather(warp.row_mass, slice_ * rows + row + 1, active)
            self.lines.append((line0, line0 + columns, near, far, cdf_near, cdf_far))
        mass = warp.strip_mass(corners, row, active)
        r0, r1 = warp.row_mass_of(corners, row, active), warp.row_mass_of(corners, row + 1, active)
        across = ((mass / warp.marginal(corners, rows - 1, active)) * ((1 - down) * r0 + down * r1)
                  / (0.5 * (r0 + r1) * warp.row_axis.width))
        self.across_rows = dr.select(mass > 0, across, 0)
        self.total = self.cdf(columns - 1)

    def _blend(self, array, column, weights):
        """Sum over the corners' two vertex rows of their weights (a slice of a line) x array at `column`."""
        gather = self.warp.gather
        total = 0
        for line in self.lines:
            near, far = line[weights]
            total += near * gather(array, line[0] + column, self.active) + far * gather(array, line[1] + column,
                                                                                        self.active)
        return total

    def cdf(self, column):
        """The blended conditional CDF at vertex `column`, unnormalised."""
        return self._blend(self.warp.row_cdf, column, slice(4, 6))

    def cell_mass(self, column):
        """The mass of cell [column, column + 1]: the sum of the rows' steps, positive wherever one is."""
        gather, cdfs = self.warp.gather, self.warp.row_cdf
        total = 0
        for line0, line1, _, _, cdf_near, cdf_far in self.lines:
            step0 = gather(cdfs, line0 + column + 1, self.active) - gather(cdfs, line0 + column, self.active)
            step1 = gather(cdfs, line1 + column + 1, self.active) - gather(cdfs, line1 + column, self.active)
            total += cdf_near * step0 + cdf_far * step1
        return total

    def value(self, column):
        """The blended density at vertex `column` of the line."""
        return self._blend(self.warp.density, column, slice(2, 4))

    def density(self, column, right):
        """The sampled law's density at fraction `right` of cell `column` on the line; 0 without mass."""
        mass = self.cell_mass(column)
        c0, c1 = self.value(column), self.value(column + 1)
        density = (self.across_rows * (mass / self.total) * ((1 - right) * c0 + right * c1)
                   / (0.5 * (c0 + c1) * self.warp.column_axis.width))
        return dr.select((self.across_rows > 0) & (mass > 0), density, 0)


class _DrjitBilinear2D:
    """An acdf Bilinear2D warp conditioned on RGL's two parameters (sampling/bilinear_2d.h; the arrays
    of acdf.RglBrdfSampler.warp_arrays) in a JIT variant's arrays, sampled, evaluated and inverted as
    its C++ does: the 2^2 neighbouring slices blended, every query in float64, coordinates and
    densities rounded to float32. Points are (x0, x1): x0 along the rows."""

    def __init__(self, mi, arrays):
        self.mi = mi
        _, self.rows, self.columns = arrays["density"].shape
        self.parameter_values = [np.asarray(v, dtype=np.float32) for v in arrays["parameter_values"]]
        # Slices between consecutive values of a parameter: row-major, the last parameter fastest.
        self.strides = [int(np.prod([len(v) for v in self.parameter_values[p + 1:]]))
                        for p in range(len(self.parameter_values))]
        self.values = [mi.Float(v) for v in self.parameter_values]
        self.density, self.row_cdf = mi.Float(arrays["density"].ravel()), mi.Float(arrays["row_cdf"].ravel())
        self.row_mass, self.marginal_cdf = mi.Float(arrays["row_mass"].ravel()), mi.Float(arrays["marginal"].ravel())
        self.row_axis, self.column_axis = _DrjitAxis((0, 1), self.rows - 1), _DrjitAxis((0, 1), self.columns - 1)

    @property
    def bytes(self):
        """Of its arrays."""
        arrays = [self.density, self.row_cdf, self.row_mass, self.marginal_cdf, *self.values]
        return 4 * sum(dr.width(a) for a in arrays)

    def gather(self, array, index, active):
        return self.mi.Float64(dr.gather(self.mi.Float, array, index, active))

    def _blend(self, params, active):
        """The slices the parameter point (float32 per parameter) reads, as (slice, weight) corners in
        Bilinear2D::blend's order. A parameter on one of its values still splits its corners, the
        second with weight 0 (its slice kept in range), so every lane has 2^parameters corners."""
        mi = self.mi
        corners = [(mi.UInt32(0), mi.Float64(1))]
        for values, array, stride, x in zip(self.parameter_values, self.values, self.strides, params):
            n = len(values)
            if n == 1:
                continue
            at_most = sum(dr.select(x >= float(v), mi.UInt32(1), mi.UInt32(0)) for v in values)  # std::upper_bound
            interior = x > float(values[0])  # NaN and the first value take the first interval
            at_end = x >= float(values[-1])
            first = dr.select(interior, dr.select(at_end, n - 2, at_most - 1), 0)
            lower = mi.Float64(dr.gather(mi.Float, array, first, active))
            upper = mi.Float64(dr.gather(mi.Float, array, first + 1, active))
            alpha = dr.select(interior, dr.select(at_end, 1, (mi.Float64(x) - lower) / (upper - lower)), 0)
            first = dr.select(alpha == 1, first + 1, first)
            alpha = dr.select(alpha == 1, 0, alpha)
            second = dr.minimum(first + 1, n - 1)
            corners = ([(s + first * stride, w * (1 - alpha)) for s, w in corners]
                       + [(s + second * stride, w * alpha) for s, w in corners])
        return corners

    def _sum(self, corners, array, offset, active):
        """Sum over the corners of weight x array[slice x rows + offset]."""
        total = 0
        for slice_, weight in corners:
            total += weight * self.gather(array, slice_ * self.rows + offset, active)
        return total

    def marginal(self, corners, row, active):
        return self._sum(corners, self.marginal_cdf, row, active)

    def row_mass_of(self, corners, row, active):
        return self._sum(corners, self.row_mass, row, active)

    def strip_mass(self, corners, row, active):
        """The strip's mass: the sum of the slices' steps of the marginal CDF."""
        total = 0
        for slice_, weight in corners:
            at = slice_ * self.rows + row
            total += weight * (self.gather(self.marginal_cdf, at + 1, active) - self.gather(self.marginal_cdf, at,
                                                                                           active))
        return total

    def _fraction(self, axis, x, cell):
        """The position of float32 x inside its cell, in float64 (fraction, bilinear_2d.cpp)."""
        return dr.clip(axis.grid_coordinate(self.mi, x), 0, axis.cells) - self.mi.Float64(cell)

    def sample(self, params, u0, u1, active):
        """x0, x1 (float32) and their density (float32) for variates u0, u1 in [0, 1) (float32)."""
        mi = self.mi
        corners = self._blend(params, active)
        rows, columns = self.rows, self.columns
        row_target = mi.Float64(u0) * self.marginal(corners, rows - 1, active)
        row = _find_interval(mi, rows, row_target, lambda r: self.marginal(corners, r, active))
        down = _sample_linear_segment((row_target - self.marginal(corners, row, active))
                                      / self.strip_mass(corners, row, active),
                                      self.row_mass_of(corners, row, active),
                                      self.row_mass_of(corners, row + 1, active))
        x0 = self.row_axis.place(mi, mi.Float64(row) + down, row, row + 1)
        # The columns are sampled on the float coordinate's line; a line through a vertex row of no
        # mass has none: one float inwards.
        empty = _DrjitStrip(self, corners, row, self._fraction(self.row_axis, x0, row), active).total <= 0
        x0 = dr.select(empty, _next_float_up(mi, x0), x0)
        strip = _DrjitStrip(self, corners, row, self._fraction(self.row_axis, x0, row), active)

        column_target = mi.Float64(u1) * strip.total
        column = _find_interval(mi, columns, column_target, strip.cdf)
        c0 = strip.value(column)
        right = _sample_linear_segment((column_target - strip.cdf(column)) / strip.cell_mass(column), c0,
                                       strip.value(column + 1))
        x1 = self.column_axis.place(mi, mi.Float64(column) + right, column, column + 1)
        placed = self._fraction(self.column_axis, x1, column)
        on_zero_vertex = (placed == 0) & (c0 == 0)
        x1 = dr.select(on_zero_vertex, _next_float_up(mi, x1), x1)
        placed = dr.select(on_zero_vertex, self._fraction(self.column_axis, x1, column), placed)
        return x0, x1, _clamp_density(mi, strip.density(column, placed))

    def pdf(self, params, x0, x1, active):
        """The density (float32) at the float32 point (x0, x1); 0 outside [0, 1)^2."""
        mi = self.mi
        corners = self._blend(params, active)
        row, column = self.row_axis.cell_of(mi, x0), self.column_axis.cell_of(mi, x1)
        strip = _DrjitStrip(self, corners, row, self._fraction(self.row_axis, x0, row), active)
        density = _clamp_density(mi, strip.density(column, self._fraction(self.column_axis, x1, column)))
        inside = (x0 >= 0) & (x0 < 1) & (x1 >= 0) & (x1 < 1)
        return dr.select(inside, density, 0)

    def invert(self, params, x0, x1, active):
        """The variates (float32, in [0, 1)) sample() maps to (x0, x1), up to float rounding."""
        mi = self.mi
        corners = self._blend(params, active)
        row, column = self.row_axis.cell_of(mi, x0), self.column_axis.cell_of(mi, x1)
        down, right = self._fraction(self.row_axis, x0, row), self._fraction(self.column_axis, x1, column)
        u0 = ((self.marginal(corners, row, active) + self.strip_mass(corners, row, active)
               * _linear_segment_cdf(down, self.row_mass_of(corners, row, active),
                                     self.row_mass_of(corners, row + 1, active)))
              / self.marginal(corners, self.rows - 1, active))
        strip = _DrjitStrip(self, corners, row, down, active)
        u1 = (strip.cdf(column) + strip.cell_mass(column) * _linear_segment_cdf(right, strip.value(column),
                                                                               strip.value(column + 1))) / strip.total
        u1 = dr.select(strip.total > 0, u1, 0)
        return (dr.clip(mi.Float(u0), 0, _below(1)), dr.clip(mi.Float(u1), 0, _below(1)))


def _elevation(d):
    """theta of a unit vector as acdf's RglBrdf::elevation: 2 asin(|d - z| / 2), exact near the normal."""
    distance = dr.sqrt(d.x * d.x + d.y * d.y + (d.z - 1) * (d.z - 1))
    return 2 * dr.asin(dr.minimum(0.5 * distance, 1))


class _DrjitRglWarps:
    """An acdf.RglBrdfSampler (brdf/rgl_sampler.h: the RGL file's luminance warp, then its visible-NDF
    warp, both conditioned on omega_o's (phi_o, theta_o) in float32) in a JIT variant's arrays: the
    half vector's unit coordinates um = (v, u) at theta_m = u^2 pi / 2, phi_m = phi_o + (2 v - 1) pi,
    omega_o reflected about it, p(omega_m) = p_lum(s) p_vndf(um) / (2 pi^2 u sin theta_m) per
    steradian. A sample reports pdf() of its omega_i (where positive; C++ reports the density along
    the path, which pdf() matches to float rounding), so that the two agree bit for bit."""

    def __init__(self, mi, sampler):
        self.mi = mi
        arrays = sampler.warp_arrays
        self.luminance = _DrjitBilinear2D(mi, arrays["luminance"])
        self.vndf = _DrjitBilinear2D(mi, arrays["vndf"])

    @property
    def bytes(self):
        """Of its arrays."""
        return self.luminance.bytes + self.vndf.bytes

    def _parameters(self, wo):
        """The warps' parameters of omega_o, float32 (RglBrdf::parameters)."""
        return [self.mi.Float(dr.atan2(wo.y, wo.x)), self.mi.Float(_elevation(wo))]

    @staticmethod
    def _per_steradian(density, u, theta):
        """A density of um on the unit square per steradian of omega_m (at the normal itself the
        smallest positive Jacobian keeps it finite)."""
        jacobian = 2 * np.pi * np.pi * u * dr.sin(theta)
        return density / dr.maximum(jacobian, float(np.finfo(np.float64).tiny))

    def pdf(self, wo, wi, active):
        """Density of omega_i (float64 unit vectors) given omega_o above the horizon, per steradian."""
        mi = self.mi
        h, cos_out, valid = _half_vector(wo, wi, active)
        params = self._parameters(wo)
        theta = _elevation(h)
        v = (dr.atan2(h.y, h.x) - mi.Float64(params[0]) + np.pi) / (2 * np.pi)
        um = (mi.Float(v - dr.floor(v)), mi.Float(dr.sqrt(dr.maximum(theta, 0) * (2 / np.pi))))
        s = self.vndf.invert(params, *um, valid)
        density = mi.Float64(self.luminance.pdf(params, *s, valid)) * mi.Float64(self.vndf.pdf(params, *um, valid))
        return dr.select(valid, self._per_steradian(density, mi.Float64(um[1]), theta) / (4 * cos_out), 0)

    def sample(self, wo, u, active):
        """omega_i and its density for omega_o (float64, above the horizon) and variates u (Point2f)."""
        mi = self.mi
        params = self._parameters(wo)
        s0, s1, s_density = self.luminance.sample(params, *_unit_variates(u), active)
        v, u_m, um_density = self.vndf.sample(params, s0, s1, active)
        u_m = mi.Float64(u_m)
        theta = u_m * u_m * (np.pi / 2)
        sin_theta = dr.sin(theta)
        sin_phi, cos_phi = dr.sincos((2 * mi.Float64(v) - 1) * np.pi + mi.Float64(params[0]))
        wm = mi.Vector3d(sin_theta * cos_phi, sin_theta * sin_phi, dr.cos(theta))
        cos_out = dr.dot(wo, wm)
        wi = dr.normalize(wm * (2 * cos_out) - wo)
        density = self._per_steradian(mi.Float64(s_density) * mi.Float64(um_density), u_m, theta)
        along_path = density / (4 * dr.abs(cos_out))
        found = self.pdf(wo, wi, active)
        return wi, dr.select(found > 0, found, along_path)


_FAR = 1e15
_ONE_MINUS_EPSILON = 1 - 2**-24  # the largest float below 1, as acdf clamps variates (clampUnit)
_envmap_classes = []  # AcdfEnvmap of each variant register() was called in

_SAMPLINGS = ("adaptive", "uniform", "rgl", "cosine")


def _usable(rows):
    """Rows that are directions (finite, not zero: an inactive lane's may be neither),
    and the rows with the others replaced by +z so that acdf accepts them."""
    ok = np.all(np.isfinite(rows), axis=1) & (np.linalg.norm(rows, axis=1) > 0.5)
    return ok, np.where(ok[:, None], rows, [[0.0, 0.0, 1.0]])


def _sampling_of(props):
    return str(props["sampling"]) if "sampling" in props else "adaptive"


class _DrjitMerl:
    """A MERL table (acdf.MerlBrdf, looked up as acdf and MERL's BRDFRead.cpp do: the cell of the
    Rusinkiewicz angles, brdf/merl.h, coordinates.h) in a JIT variant's arrays, evaluated by drjit
    operations in float64 as in C++. eval() is Mitsuba's: f times the cosine of the light direction."""

    def __init__(self, mi, model):
        self.mi = mi
        self.values = mi.Float(model.values.reshape(-1))  # the rgb of cell 0, of cell 1, ...
        self.scale = model.channel_scale
        self.cells = model.cells  # theta_h, theta_d, phi_d

    @staticmethod
    def _index(g, cells):
        """A grid coordinate's cell, clamped; 0 for NaN (clampIndex)."""
        return dr.select(g > 0, dr.minimum(g, cells - 1), 0)

    def cell(self, wo, wi):
        """The flat index of the cell of (omega_o, omega_i), float64 unit vectors above the horizon."""
        mi = self.mi
        half = wi + wo
        rho = dr.sqrt(half.x * half.x + half.y * half.y)
        length = dr.sqrt(rho * rho + half.z * half.z)
        cos_phi, sin_phi = dr.select(rho > 0, half.x / rho, 1), dr.select(rho > 0, half.y / rho, 0)
        cos_theta, sin_theta = dr.select(length > 0, half.z / length, 1), dr.select(length > 0, rho / length, 0)
        # The difference vector: omega_i turned by -phi_h about z, then by -theta_h about y.
        x, y = cos_phi * wi.x + sin_phi * wi.y, cos_phi * wi.y - sin_phi * wi.x
        d_x, d_z = cos_theta * x - sin_theta * wi.z, cos_theta * wi.z + sin_theta * x
        # With either direction on the normal, phi_d is 0 or pi exactly (acdf drops the residue).
        on_normal = ((wo.x == 0) & (wo.y == 0)) | ((wi.x == 0) & (wi.y == 0))
        d_y = dr.select(on_normal, 0, y)
        theta_half = dr.select(length > 0, dr.atan2(rho, half.z), 0)
        theta_diff = dr.atan2(dr.sqrt(d_x * d_x + d_y * d_y), d_z)
        phi_diff = dr.atan2(d_y, d_x)  # (-pi, pi], folded into [0, pi) by reciprocity
        phi_diff = dr.select(dr.abs(phi_diff) == np.pi, 0, phi_diff)
        phi_diff = dr.select(phi_diff < 0, phi_diff + np.pi, phi_diff)
        phi_diff = dr.select(phi_diff >= np.pi, phi_diff - np.pi, phi_diff)
        h_cells, d_cells, p_cells = self.cells
        h = self._index(dr.sqrt(theta_half / (np.pi / 2) * h_cells * h_cells), h_cells)
        d = self._index(theta_diff / (np.pi / 2) * d_cells, d_cells)
        p = self._index(phi_diff / np.pi * p_cells, p_cells)
        return (mi.UInt32(h) * d_cells + mi.UInt32(d)) * p_cells + mi.UInt32(p)

    def eval(self, ctx, si, wo, active=True):
        mi = self.mi
        viewer, light = dr.normalize(mi.Vector3d(si.wi)), dr.normalize(mi.Vector3d(wo))
        up = active & (viewer.z > 0) & (light.z > 0)
        index = 3 * self.cell(viewer, light)
        f = [mi.Float(mi.Float64(dr.gather(mi.Float, self.values, index + c, up)) * self.scale[c]) for c in range(3)]
        return dr.select(up, mi.Color3f(*f) * mi.Float(light.z), 0)


def _make_measured_classes():
    """(BatchedMeasured, NativeMeasured) of the current variant."""
    mi = _mi()
    class AcdfMeasured(mi.BSDF):
        """What both implementations share: the parameters, the model and acdf's sampler."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            name = "acdf_measured"
            _refuse_unknown(name, props, ["filename", "sampling", *_MEASURED_TABLE_OPTIONS])
            if "filename" not in props:
                _refuse(name, "needs a filename (MERL .binary or RGL .bsdf)")
            filename = str(props["filename"])
            sampling = _sampling_of(props)
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
            self.model = model
            self.filename = filename
            self.sampling = sampling
            self.bytes = self.sampler.bytes  # of acdf's sampling tables
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [flags]
            self.m_flags = flags

        def to_string(self):
            return f"AcdfMeasured[sampling={self.sampling}, bytes={self.bytes}]"

    class BatchedMeasured(AcdfMeasured):
        """Every file and sampling, in the scalar variants: each call one acdf call on a batch of one row
        (the JIT variants' acdf_measured is NativeMeasured)."""

        # Mitsuba's si.wi points to the viewer and its wo to the light; acdf's wo is the viewer
        # and wi the light. Mitsuba's eval includes the cosine of the light direction; acdf's does not.
        def _pair(self, si, wo):
            ok_v, viewer = _usable(_rows(si.wi))
            ok_l, light = _usable(_rows(wo))
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
            ok, viewer = _usable(_rows(si.wi))
            ok &= viewer[:, 2] > 0
            light, weight, pdf = self.sampler.sample(viewer, u)
            ok &= (pdf > 0) & (light[:, 2] > 0)
            bs = mi.BSDFSample3f()
            bs.wo = _vector(mi, light)
            bs.pdf = _float(mi, np.where(ok, pdf, 0.0))
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            return bs, _color(mi, np.where(ok[:, None], weight, 0.0))

    class NativeMeasured(AcdfMeasured):
        """JIT variants, every sampling: acdf's table (_DrjitHalfVectorTable) or the RGL file's warps
        (_DrjitRglWarps) as arrays of the variant, or cosine-weighted, sampled and the pdf answered by
        drjit operations that Mitsuba records into its kernels. The BRDF's value: of an RGL file, Mitsuba's own measured
        plugin loaded from the same file, which acdf's RglBrdf equals (tests/python/test_mitsuba.py),
        clamped at 0 as acdf's is; of a MERL file, its table in drjit (_DrjitMerl). No Python or acdf
        call per wavefront."""

        def __init__(self, props):
            AcdfMeasured.__init__(self, props)
            model = self.model
            self.reflectance = (_DrjitMerl(mi, model) if isinstance(model, acdf.MerlBrdf)
                                else mi.load_dict({"type": "measured", "filename": self.filename}))
            tables = {"cosine": lambda mi, sampler: None, "rgl": _DrjitRglWarps}
            self.table = tables.get(self.sampling, _DrjitHalfVectorTable)(mi, self.sampler)
            # The arrays are all it samples and evaluates with: acdf's model and C++ table go.
            del self.sampler, self.model

        def _value(self, ctx, si, wo, active):
            return dr.maximum(self.reflectance.eval(ctx, si, wo, active), 0)

        def eval(self, ctx, si, wo, active=True):
            return self._value(ctx, si, wo, active)

        def pdf(self, ctx, si, wo, active=True):
            # Mitsuba's viewer and light directions are acdf's wo and wi.
            viewer, light = dr.normalize(mi.Vector3d(si.wi)), dr.normalize(mi.Vector3d(wo))
            up = active & (viewer.z > 0) & (light.z > 0)
            pdf = _cosine_pdf(light.z) if self.table is None else self.table.pdf(viewer, light, up)
            return dr.select(up, mi.Float(pdf), 0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            viewer = dr.normalize(mi.Vector3d(si.wi))
            ok = active & (viewer.z > 0)
            if self.table is None:
                light, pdf = _cosine_sample(mi, *_unit_variates(sample2))
            else:
                light, pdf = self.table.sample(viewer, sample2, ok)
            ok &= (pdf > 0) & (light.z > 0)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = mi.Vector3f(light)
            bs.pdf = dr.select(ok, mi.Float(pdf), 0)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            value = self._value(ctx, si, bs.wo, ok)
            return bs, dr.select(ok, value / dr.select(ok, bs.pdf, 1), 0)

    return BatchedMeasured, NativeMeasured


def register():
    """Registers acdf_envmap and acdf_measured with Mitsuba for the current variant (call after
    mi.set_variant): the native drjit classes in JIT variants, the batched ones in scalar variants.
    drjit's flags are left as they are: Mitsuba traces the native classes into its kernels with the
    symbolic loops and calls on, drjit's default."""
    mi = _mi()
    base, batched, native = _make_envmap_classes()
    _envmap_classes.append(base)
    batched_measured, native_measured = _make_measured_classes()
    jit = dr.is_jit_v(mi.Float)
    mi.register_emitter("acdf_envmap", native if jit else batched)
    mi.register_bsdf("acdf_measured", native_measured if jit else batched_measured)


def _with_scene(scene):
    for emitter in scene.emitters():
        if isinstance(emitter, tuple(_envmap_classes)):
            emitter.set_scene(scene)
    return scene


def load_dict(scene_dict, **kwargs):
    """mi.load_dict, then gives acdf_envmap emitters the scene: its bounding sphere (needed by
    sample_ray: light tracing, e.g. Mitsuba's ptracer; path tracing does not need it) and, where they
    declare no portal, the openings found in it (portals "auto")."""
    return _with_scene(_mi().load_dict(scene_dict, **kwargs))


def load_file(path, **kwargs):
    """mi.load_file, then as load_dict."""
    return _with_scene(_mi().load_file(path, **kwargs))
