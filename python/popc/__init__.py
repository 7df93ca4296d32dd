"""popc from Python: libpopc's public API (popc/popc.h) through ctypes.

A pure-Python package over the installed libpopc.so: it needs python3 and
python3-numpy, and pandas only for Log.dataframe() (docs/LIBRARY.md,
"Python"). Every number comes from the library the programs use, so a log
read here, a run made here and a controller stepped here give the bits
`popc run` and `popc-analyze` give.

    import popc
    scene = popc.Scene("paper")                  # an installed scene, or a path
    scene.set("controller.variant", "improved")
    log = popc.run(scene)                        # as `popc run paper --log ...`
    log.header["variant"], log.rows["f_c"]       # a dict, a numpy structured array
    port = popc.Port(scene)                      # the VE and PO/PC
    tick = port.step(count)                      # count in, tick.f_c_N out
"""
import ctypes
import os
import tempfile

import numpy

try:
    from ._config import LIBDIR
except ImportError:  # the source tree: POPC_LIBRARY names the built library
    LIBDIR = None

__all__ = ["Error", "Scene", "Port", "Observer", "Sim", "Tick", "Sample", "Log",
           "AdmittancePort", "AdmittanceSim", "AdmittanceTick", "AdmittanceSample",
           "run", "read_log", "version", "api_version"]

API_MAJOR = 1  # POPC_LIB_API_VERSION_MAJOR: the soname this module was written for


def _load():
    """libpopc.so.API_MAJOR: POPC_LIBRARY (a path), else the one installed
    beside this module (LIBDIR, from meson), else the loader's search."""
    names = []
    if os.environ.get("POPC_LIBRARY"):
        names.append(os.environ["POPC_LIBRARY"])
    if LIBDIR:
        names.append(os.path.join(LIBDIR, "libpopc.so.%d" % API_MAJOR))
    names.append("libpopc.so.%d" % API_MAJOR)
    errors = []
    for name in names:
        try:
            return ctypes.CDLL(name)
        except OSError as e:
            errors.append(str(e))
    raise ImportError("popc: cannot load libpopc: " + "; ".join(errors))


_lib = _load()


class Error(Exception):
    """A failed library call: status (POPC_LIB_ERR_*) and the library's message."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status


class _Err(ctypes.Structure):
    _fields_ = [("msg", ctypes.c_char * 512)]


class Tick(ctypes.Structure):
    """popc_lib_tick: one control tick as the log has it."""
    _fields_ = [("t_s", ctypes.c_double), ("x_m", ctypes.c_double), ("count", ctypes.c_longlong),
                ("v_mps", ctypes.c_double), ("f_e_N", ctypes.c_double), ("f_pc_N", ctypes.c_double),
                ("f_c_N", ctypes.c_double), ("W_J", ctypes.c_double), ("E_ref_J", ctypes.c_double),
                ("flags", ctypes.c_uint)]


class Sample(ctypes.Structure):
    """popc_lib_sample: the simulated device's count, true position, port energy."""
    _fields_ = [("count", ctypes.c_longlong), ("x_true_m", ctypes.c_double),
                ("E_port_J", ctypes.c_double)]


class AdmittanceTick(ctypes.Structure):
    """popc_lib_admittance_tick: what an admittance tick adds (API 1.1)."""
    _fields_ = [("f_count", ctypes.c_longlong), ("f_meas_N", ctypes.c_double),
                ("x_ve_m", ctypes.c_double), ("v_ve_mps", ctypes.c_double),
                ("v_pc_mps", ctypes.c_double), ("v_c_mps", ctypes.c_double)]


class AdmittanceSample(ctypes.Structure):
    """popc_lib_admittance_sample: the admittance device's counts and positions (API 1.1)."""
    _fields_ = [("count", ctypes.c_longlong), ("force_count", ctypes.c_longlong),
                ("x_true_m", ctypes.c_double), ("x_cmd_m", ctypes.c_double)]


_P = ctypes.c_void_p
_E = ctypes.POINTER(_Err)


def _sig(name, restype, *argtypes):
    f = getattr(_lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)
    return f


_api_version = _sig("popc_lib_api_version", ctypes.c_uint)
_version = _sig("popc_lib_version", ctypes.c_char_p)
_scene_create = _sig("popc_lib_scene_create", ctypes.c_int, ctypes.POINTER(_P), _E)
_scene_load = _sig("popc_lib_scene_load", ctypes.c_int, _P, ctypes.c_char_p, _E)
_scene_set_data_path = _sig("popc_lib_scene_set_data_path", ctypes.c_int, _P, ctypes.c_char_p, _E)
_scene_set = _sig("popc_lib_scene_set", ctypes.c_int, _P, ctypes.c_char_p, ctypes.c_char_p, _E)
_scene_validate = _sig("popc_lib_scene_validate", ctypes.c_int, _P, _E)
_scene_period = _sig("popc_lib_scene_period_s", ctypes.c_double, _P)
_scene_ticks = _sig("popc_lib_scene_tick_count", ctypes.c_longlong, _P)
_scene_free = _sig("popc_lib_scene_free", None, _P)
_port_create = _sig("popc_lib_port_create_impedance", ctypes.c_int, _P, ctypes.c_double,
                    ctypes.POINTER(_P), _E)
_port_step = _sig("popc_lib_port_step", None, _P, ctypes.c_longlong, ctypes.POINTER(Tick))
_port_free = _sig("popc_lib_port_free", None, _P)
_adm_port_create = _sig("popc_lib_port_create_admittance", ctypes.c_int, _P, ctypes.POINTER(_P), _E)
_adm_port_step = _sig("popc_lib_port_step_admittance", None, _P, ctypes.c_longlong,
                      ctypes.c_longlong, ctypes.POINTER(Tick), ctypes.POINTER(AdmittanceTick))
_obs_create = _sig("popc_lib_observer_create", ctypes.c_int, _P, ctypes.POINTER(_P), _E)
_obs_step = _sig("popc_lib_observer_step", None, _P, ctypes.POINTER(Tick),
                 ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_double))
_obs_free = _sig("popc_lib_observer_free", None, _P)
_sim_create = _sig("popc_lib_sim_create", ctypes.c_int, _P, ctypes.POINTER(_P),
                   ctypes.POINTER(Sample), _E)
_sim_exchange = _sig("popc_lib_sim_exchange", ctypes.c_int, _P, ctypes.c_double,
                     ctypes.POINTER(Sample), _E)
_sim_free = _sig("popc_lib_sim_free", None, _P)
_adm_sim_create = _sig("popc_lib_sim_create_admittance", ctypes.c_int, _P, ctypes.POINTER(_P),
                       ctypes.POINTER(AdmittanceSample), _E)
_adm_sim_exchange = _sig("popc_lib_sim_exchange_admittance", ctypes.c_int, _P, ctypes.c_double,
                         ctypes.POINTER(AdmittanceSample), _E)
_run = _sig("popc_lib_run", ctypes.c_int, _P, ctypes.c_char_p, _E)
_reader_open = _sig("popc_lib_log_reader_open", ctypes.c_int, ctypes.POINTER(_P), ctypes.c_char_p, _E)
_reader_ncols = _sig("popc_lib_log_reader_column_count", ctypes.c_int, _P)
_reader_col = _sig("popc_lib_log_reader_column_name", ctypes.c_char_p, _P, ctypes.c_int)
_reader_nkeys = _sig("popc_lib_log_reader_header_count", ctypes.c_int, _P)
_reader_key = _sig("popc_lib_log_reader_header_key", ctypes.c_char_p, _P, ctypes.c_int)
_reader_value = _sig("popc_lib_log_reader_header_value", ctypes.c_char_p, _P, ctypes.c_int)
_reader_next = _sig("popc_lib_log_reader_next", ctypes.c_int, _P, ctypes.POINTER(ctypes.c_double), _E)
_reader_stop = _sig("popc_lib_log_reader_stop_reason", ctypes.c_char_p, _P)
_reader_close = _sig("popc_lib_log_reader_close", None, _P)
_scene_from_log = _sig("popc_lib_scene_from_log", ctypes.c_int, _P, _P, _E)

if _api_version() >> 16 != API_MAJOR:
    raise ImportError("popc: libpopc's API version %#x is not %d.x" % (_api_version(), API_MAJOR))


def _check(status, err):
    if status:
        raise Error(status, err.msg.decode("utf-8", "replace"))


def _b(text):
    return os.fsencode(text) if isinstance(text, (str, os.PathLike)) else bytes(text)


def version():
    """popc's release, as `popc --version` prints it."""
    return _version().decode()


def api_version():
    """The library's API version as (major, minor, patch)."""
    v = _api_version()
    return (v >> 16, (v >> 8) & 0xFF, v & 0xFF)


class _Handle:
    _free = None

    def __init__(self):
        self._h = _P()

    def close(self):
        if self._h:
            type(self)._free(self._h)
            self._h = _P()

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class Scene(_Handle):
    """A scene: the defaults, a scene file or installed name over them, and
    `section.key=value` settings (popc-scene(5)); errors name the key and range.
    A bare name is looked up in data_path (DIR[:DIR...], as POPC_DATA_PATH),
    by default POPC_DATA_PATH's value, as popc run does: the C library reads
    no environment, the module passes it."""
    _free = _scene_free

    def __init__(self, path=None, data_path=None, **settings):
        super().__init__()
        err = _Err()
        _check(_scene_create(ctypes.byref(self._h), err), err)
        if data_path is None:
            data_path = os.environ.get("POPC_DATA_PATH")
        if data_path is not None:
            _check(_scene_set_data_path(self._h, _b(data_path), err), err)
        if path is not None:
            _check(_scene_load(self._h, _b(path), err), err)
        for key, value in settings.items():  # section__key=value
            self.set(key.replace("__", "."), value)

    @classmethod
    def from_log(cls, path, data_path=None):
        """The scene a popc log was made with: its header's section.key lines
        over the defaults (popc_lib_scene_from_log), as popc-analyze reads it;
        a recorded log without popc's header raises Error."""
        scene = cls(data_path=data_path)
        err = _Err()
        r = _P()
        _check(_reader_open(ctypes.byref(r), _b(path), err), err)
        try:
            _check(_scene_from_log(scene._h, r, err), err)
        finally:
            _reader_close(r)
        return scene

    def set(self, key, value):
        err = _Err()
        if isinstance(value, float):
            value = repr(value)  # the shortest text that reads back to the same double
        _check(_scene_set(self._h, _b(key), _b(str(value)), err), err)
        return self

    def validate(self):
        err = _Err()
        _check(_scene_validate(self._h, err), err)

    @property
    def period_s(self):
        return _scene_period(self._h)

    @property
    def tick_count(self):
        return _scene_ticks(self._h)


class Port(_Handle):
    """The scene's virtual environment and PO/PC, impedance causality: step(count) -> Tick."""
    _free = _port_free

    def __init__(self, scene, force_limit_N=0.0):
        super().__init__()
        err = _Err()
        _check(_port_create(scene._h, float(force_limit_N), ctypes.byref(self._h), err), err)

    def step(self, count):
        t = Tick()
        _port_step(self._h, int(count), ctypes.byref(t))
        return t


class Observer(_Handle):
    """The scene variant's PO alone: step(tick) -> (W, E_ref), as popc-analyze energy."""
    _free = _obs_free

    def __init__(self, scene):
        super().__init__()
        err = _Err()
        _check(_obs_create(scene._h, ctypes.byref(self._h), err), err)

    def step(self, tick):
        W, E = ctypes.c_double(), ctypes.c_double()
        _obs_step(self._h, ctypes.byref(tick), ctypes.byref(W), ctypes.byref(E))
        return W.value, E.value


class Sim(_Handle):
    """The scene's simulated device; .sample is tick 0's, exchange(f_c) gives the next."""
    _free = _sim_free

    def __init__(self, scene):
        super().__init__()
        err = _Err()
        self.sample = Sample()
        _check(_sim_create(scene._h, ctypes.byref(self._h), ctypes.byref(self.sample), err), err)

    def exchange(self, f_c_N):
        err = _Err()
        _check(_sim_exchange(self._h, float(f_c_N), ctypes.byref(self.sample), err), err)
        return self.sample


class AdmittancePort(_Handle):
    """The scene's admittance VE, observer and parallel PC (device.causality =
    admittance): step(count, force_count) -> (Tick, AdmittanceTick)."""
    _free = _port_free

    def __init__(self, scene):
        super().__init__()
        err = _Err()
        _check(_adm_port_create(scene._h, ctypes.byref(self._h), err), err)

    def step(self, count, force_count):
        t, a = Tick(), AdmittanceTick()
        _adm_port_step(self._h, int(count), int(force_count), ctypes.byref(t), ctypes.byref(a))
        return t, a


class AdmittanceSim(_Handle):
    """The scene's simulated admittance device; .sample is tick 0's, exchange(v_c) the next."""
    _free = _sim_free

    def __init__(self, scene):
        super().__init__()
        err = _Err()
        self.sample = AdmittanceSample()
        _check(_adm_sim_create(scene._h, ctypes.byref(self._h), ctypes.byref(self.sample), err), err)

    def exchange(self, v_c_mps):
        err = _Err()
        _check(_adm_sim_exchange(self._h, float(v_c_mps), ctypes.byref(self.sample), err), err)
        return self.sample


# the integer columns of popc's log; every other column is a double
_INTEGER_COLUMNS = {"count": numpy.int64, "flags": numpy.uint32}


class Log:
    """A popc log read back: header (dict of the "# key = value" lines, keys
    qualified "run.rate"), rows (numpy structured array, one field a
    column), stop (the "# stop = ..." reason)."""

    def __init__(self, header, rows, stop):
        self.header = header
        self.rows = rows
        self.stop = stop

    def dataframe(self):
        """The rows as a pandas DataFrame (needs pandas)."""
        import pandas
        return pandas.DataFrame(self.rows)


def read_log(path):
    """Reads a popc log (or a recorded CSV log) with popc's own reader: the
    same doubles, bit for bit, that popc-analyze reads."""
    err = _Err()
    r = _P()
    _check(_reader_open(ctypes.byref(r), _b(path), err), err)
    try:
        n = _reader_ncols(r)
        names = [_reader_col(r, i).decode() for i in range(n)]
        header = {}
        for i in range(_reader_nkeys(r)):
            header[_reader_key(r, i).decode()] = _reader_value(r, i).decode()
        values = (ctypes.c_double * n)()
        chunks, chunk = [], numpy.empty((4096, n))
        used = 0
        while True:
            st = _reader_next(r, values, err)
            if st < 0:
                _check(st, err)
            if st == 0:
                break
            if used == len(chunk):
                chunks.append(chunk)
                chunk, used = numpy.empty((4096, n)), 0
            chunk[used] = numpy.frombuffer(values, dtype=numpy.float64, count=n)
            used += 1
        chunks.append(chunk[:used])
        data = numpy.concatenate(chunks) if chunks else numpy.empty((0, n))
        stop = _reader_stop(r).decode()
    finally:
        _reader_close(r)
    dtype = [(name, _INTEGER_COLUMNS.get(name, numpy.float64)) for name in names]
    rows = numpy.empty(len(data), dtype=dtype)
    for i, name in enumerate(names):
        rows[name] = data[:, i]
    return Log(header, rows, stop)


def run(scene, log_path=None):
    """Runs the scene as `popc run` does and returns its Log. The log is
    written to log_path when given, else to a temporary file removed after."""
    err = _Err()
    if log_path is not None:
        _check(_run(scene._h, _b(log_path), err), err)
        return read_log(log_path)
    with tempfile.TemporaryDirectory(prefix="popc-") as d:
        path = os.path.join(d, "run.csv")
        _check(_run(scene._h, _b(path), err), err)
        return read_log(path)
