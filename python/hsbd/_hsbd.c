/* hsbd._hsbd: the C half of the Python package `hsbd` (python/hsbd/__init__.py is the
 * other), a CPython extension over the public C API. Simulations built from a
 * configuration file, a dict or keyword arguments (the schema of docs/config.md), stepped
 * from Python, with the state as read-only numpy views and the observers' results; the
 * exact theory; runs written as `hsbd run` writes them. Documentation: docs/python.md and
 * the docstrings (each starts with its signature for inspect.signature). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/hsbd.h"

static PyObject *hsbd_error_type;  /* hsbd.Error (RuntimeError) */
static PyObject *hsbd_input_error; /* hsbd.InputError (hsbd.Error, ValueError) */

static PyObject *raise_error(const hsbd_error *err) {
    PyErr_SetString(err->status == HSBD_EINPUT   ? hsbd_input_error
                    : err->status == HSBD_ENOMEM ? PyExc_MemoryError
                                                 : hsbd_error_type,
                    err->message);
    return NULL;
}

/* ---- configurations: a file, a dict, keyword arguments ---- */

/* "section.key=value" assignments collected from Python, kept for the run's source. */
typedef struct assignments {
    char **text;
    size_t n, cap;
} assignments;

static void assignments_free(assignments *a) {
    for (size_t k = 0; k < a->n; ++k)
        free(a->text[k]);
    free(a->text);
    *a = (assignments){0};
}

/* The text of a value: str as it is, bool as on/off, numbers by repr (round-trip exact),
 * sequences joined by commas. */
static PyObject *value_text(PyObject *v) {
    if (PyUnicode_Check(v)) return Py_NewRef(v);
    if (PyBool_Check(v)) return PyUnicode_FromString(v == Py_True ? "on" : "off");
    if (PyList_Check(v) || PyTuple_Check(v)) {
        PyObject *parts = PyList_New(0);
        if (!parts) return NULL;
        const Py_ssize_t n = PySequence_Size(v);
        for (Py_ssize_t k = 0; k < n; ++k) {
            PyObject *item = PySequence_GetItem(v, k);
            PyObject *t = item ? value_text(item) : NULL;
            Py_XDECREF(item);
            if (!t || PyList_Append(parts, t) != 0) {
                Py_XDECREF(t);
                Py_DECREF(parts);
                return NULL;
            }
            Py_DECREF(t);
        }
        PyObject *sep = PyUnicode_FromString(",");
        PyObject *joined = sep ? PyUnicode_Join(sep, parts) : NULL;
        Py_XDECREF(sep);
        Py_DECREF(parts);
        return joined;
    }
    return PyObject_Repr(v);
}

static int assign(hsbd_config *cfg, assignments *a, const char *key, PyObject *value,
                  const char *origin) {
    PyObject *t = value_text(value);
    if (!t) return -1;
    const char *vs = PyUnicode_AsUTF8(t);
    char *text = vs ? malloc(strlen(key) + strlen(vs) + 2) : NULL;
    if (!text) {
        Py_DECREF(t);
        if (!PyErr_Occurred()) PyErr_NoMemory();
        return -1;
    }
    sprintf(text, "%s=%s", key, vs);
    Py_DECREF(t);
    if (a->n == a->cap) {
        const size_t cap = a->cap ? 2 * a->cap : 16;
        char **grown = realloc(a->text, cap * sizeof *grown);
        if (!grown) {
            free(text);
            PyErr_NoMemory();
            return -1;
        }
        a->text = grown, a->cap = cap;
    }
    a->text[a->n++] = text;
    hsbd_error err;
    if (hsbd_config_set(cfg, text, origin, &err) != HSBD_OK) {
        raise_error(&err);
        return -1;
    }
    return 0;
}

/* {"section.key": value} or {"section": {"key": value}} */
static int assign_dict(hsbd_config *cfg, assignments *a, PyObject *dict, const char *origin) {
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    while (PyDict_Next(dict, &pos, &key, &value)) {
        const char *k = PyUnicode_Check(key) ? PyUnicode_AsUTF8(key) : NULL;
        if (!k) {
            PyErr_SetString(PyExc_TypeError, "configuration keys are strings");
            return -1;
        }
        if (PyDict_Check(value)) {
            PyObject *inner_key, *inner;
            Py_ssize_t ipos = 0;
            while (PyDict_Next(value, &ipos, &inner_key, &inner)) {
                const char *ik = PyUnicode_Check(inner_key) ? PyUnicode_AsUTF8(inner_key) : NULL;
                if (!ik) {
                    PyErr_SetString(PyExc_TypeError, "configuration keys are strings");
                    return -1;
                }
                char full[256];
                snprintf(full, sizeof full, "%s.%s", k, ik);
                if (assign(cfg, a, full, inner, origin) != 0) return -1;
            }
        } else if (assign(cfg, a, k, value, origin) != 0) {
            return -1;
        }
    }
    return 0;
}

/* A finalized configuration from `config` (None, a path, or a dict) and keyword
 * arguments (sections as dicts: system={"N": 50}); the file's path and text and the
 * assignments go to `source` (for checkpoints). */
typedef struct built_config {
    hsbd_config cfg;
    assignments sets;
    char *path, *text;
    size_t text_len;
} built_config;

static void built_config_free(built_config *b) {
    assignments_free(&b->sets);
    free(b->path);
    free(b->text);
    b->path = b->text = NULL;
}

static char *read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = NULL;
    size_t n = 0, cap = 0, got;
    do {
        if (n + 4096 + 1 > cap) {
            cap = 2 * (n + 4096 + 1);
            char *grown = realloc(text, cap);
            if (!grown) break;
            text = grown;
        }
        got = fread(text + n, 1, cap - n - 1, f);
        n += got;
    } while (got > 0);
    fclose(f);
    if (text) text[n] = '\0';
    *len = n;
    return text;
}

static int build_config(PyObject *config, PyObject *kwargs, built_config *b) {
    hsbd_error err;
    hsbd_config_defaults(&b->cfg);
    if (config && config != Py_None && !PyDict_Check(config)) {
        PyObject *p = PyOS_FSPath(config);
        if (!p) return -1;
        PyObject *bytes = NULL;
        if (!PyUnicode_FSConverter(p, &bytes)) {
            Py_DECREF(p);
            return -1;
        }
        Py_DECREF(p);
        b->path = strdup(PyBytes_AS_STRING(bytes));
        Py_DECREF(bytes);
        if (!b->path) return PyErr_NoMemory(), -1;
        if (hsbd_config_load_file(&b->cfg, b->path, &err) != HSBD_OK) return raise_error(&err), -1;
        b->text = read_file(b->path, &b->text_len);
        if (!b->text) return PyErr_SetFromErrnoWithFilename(PyExc_OSError, b->path), -1;
    } else if (config && PyDict_Check(config) &&
               assign_dict(&b->cfg, &b->sets, config, "Python (configuration dict)") != 0) {
        return -1;
    }
    if (kwargs) {
        PyObject *key, *value;
        Py_ssize_t pos = 0;
        while (PyDict_Next(kwargs, &pos, &key, &value))
            if (!PyDict_Check(value)) {
                PyErr_Format(PyExc_TypeError,
                             "keyword '%U': give a section's keys as a dict, e.g. "
                             "system={'N': 50}",
                             key);
                return -1;
            }
        if (assign_dict(&b->cfg, &b->sets, kwargs, "Python (keyword arguments)") != 0) return -1;
    }
    return 0;
}

static int finalize_config(built_config *b) {
    hsbd_error err;
    if (hsbd_config_finalize(&b->cfg, &err) != HSBD_OK) return raise_error(&err), -1;
    return 0;
}

/* ---- the Simulation type ---- */

/* The simulation is held by a capsule that the arrays over its memory keep alive: an
 * array taken before the positions were set (a new simulation) stays valid. */
static const char *const sim_capsule_name = "hsbd.sim";

static void sim_capsule_free(PyObject *capsule) {
    hsbd_sim_free(PyCapsule_GetPointer(capsule, sim_capsule_name));
}

typedef struct {
    PyObject_HEAD hsbd_sim *sim;
    PyObject *owner; /* the capsule of sim */
    /* rods: positions, images and diameters are computed into these at each access */
    double *x, *diameter;
    int64_t *image;
    int *species; /* rods of one species: zeros */
} SimObject;

static void sim_dealloc(SimObject *self) {
    Py_XDECREF(self->owner);
    free(self->x);
    free(self->diameter);
    free(self->image);
    free(self->species);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* self holds sim (and frees the one it held) */
static int sim_hold(SimObject *self, hsbd_sim *sim) {
    PyObject *owner = PyCapsule_New(sim, sim_capsule_name, sim_capsule_free);
    if (!owner) {
        hsbd_sim_free(sim);
        return -1;
    }
    Py_XSETREF(self->owner, owner);
    self->sim = sim;
    return 0;
}

static int sim_init(SimObject *self, PyObject *args, PyObject *kwargs) {
    PyObject *config = NULL;
    if (!PyArg_ParseTuple(args, "|O:Simulation", &config)) return -1;
    built_config b = {0};
    if (build_config(config, kwargs, &b) != 0 || finalize_config(&b) != 0) {
        built_config_free(&b);
        return -1;
    }
    hsbd_error err;
    hsbd_sim *sim;
    Py_BEGIN_ALLOW_THREADS sim = hsbd_sim_alloc(&b.cfg, &err);
    Py_END_ALLOW_THREADS built_config_free(&b);
    if (!sim) return raise_error(&err), -1;
    self->sim = NULL; /* __init__ called again: a new simulation */
    free(self->x), free(self->diameter), free(self->image), free(self->species);
    self->x = self->diameter = NULL, self->image = NULL, self->species = NULL;
    if (sim_hold(self, sim) != 0) return -1;
    const size_t n = (size_t)hsbd_sim_config(sim)->system.n;
    if (hsbd_sim_get_parts(sim).rods) {
        self->x = calloc(3 * n, sizeof *self->x);
        self->diameter = calloc(n, sizeof *self->diameter);
        self->image = calloc(3 * n, sizeof *self->image);
        self->species = calloc(n, sizeof *self->species);
        if (!self->x || !self->diameter || !self->image || !self->species)
            return PyErr_NoMemory(), -1;
    }
    return 0;
}

static int sim_ready(SimObject *self) {
    if (self->sim) return 1;
    PyErr_SetString(hsbd_error_type, "the Simulation was not built");
    return 0;
}

static PyObject *sim_step(SimObject *self, PyObject *args, PyObject *kwargs) {
    static char *kw[] = {"n", NULL};
    Py_ssize_t n = 1;
    if (!sim_ready(self) || !PyArg_ParseTupleAndKeywords(args, kwargs, "|n:step", kw, &n))
        return NULL;
    if (n < 0)
        return PyErr_Format(hsbd_input_error,
                            "step(n): n = %zd steps; allowed: n >= 0 (the run goes forward only)",
                            n),
               NULL;
    hsbd_error err;
    int rc;
    Py_BEGIN_ALLOW_THREADS rc = hsbd_sim_advance(self->sim, (uint64_t)n, &err);
    Py_END_ALLOW_THREADS if (rc != HSBD_OK) return raise_error(&err);
    Py_RETURN_NONE;
}

/* A read-only array over memory that `base` keeps alive. */
static PyObject *view(PyObject *base, void *data, int nd, npy_intp *dims, int type) {
    PyObject *a = PyArray_SimpleNewFromData(nd, dims, type, data);
    if (!a) return NULL;
    PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
    Py_INCREF(base);
    if (PyArray_SetBaseObject((PyArrayObject *)a, base) != 0) {
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

/* rods: positions wrapped into [0, L) (walls: [0, L]) as 3-vectors (y = z = 0), images,
 * diameters and species computed into the simulation's buffers */
static void rods_fill(SimObject *self) {
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    const hsbd_rods_view v = hsbd_rods_get_view(p.rods);
    for (size_t i = 0; i < v.n; ++i) {
        const double xu = v.z[i] + v.offset[i] + v.unwrap;
        const double wraps = v.periodic ? floor(xu / v.length) : 0.0;
        self->x[3 * i] = xu - wraps * v.length;
        self->image[3 * i] = (int64_t)wraps;
        self->species[i] = v.species ? v.species[i] : 0;
        self->diameter[i] = v.species ? v.species_sigma[v.species[i]] : v.sigma;
    }
}

enum { ARRAY_POSITIONS, ARRAY_IMAGES, ARRAY_DIAMETERS, ARRAY_SPECIES };

static PyObject *state_array(SimObject *self, int which) {
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    npy_intp dims[2] = {(npy_intp)hsbd_sim_config(self->sim)->system.n, 3};
    PyObject *me = (PyObject *)self;
    if (p.rods) {
        rods_fill(self);
        switch (which) {
        case ARRAY_POSITIONS:
            return view(me, self->x, 2, dims, NPY_DOUBLE);
        case ARRAY_IMAGES:
            return view(me, self->image, 2, dims, NPY_INT64);
        case ARRAY_DIAMETERS:
            return view(me, self->diameter, 1, dims, NPY_DOUBLE);
        default:
            return view(me, self->species, 1, dims, NPY_INT);
        }
    }
    const hsbd_spheres_view v = hsbd_spheres_get_view(p.spheres);
    switch (which) {
    case ARRAY_POSITIONS:
        return view(self->owner, (void *)v.x, 2, dims, NPY_DOUBLE);
    case ARRAY_IMAGES:
        return view(self->owner, (void *)v.image, 2, dims, NPY_INT64);
    case ARRAY_DIAMETERS:
        return view(self->owner, (void *)v.sigma, 1, dims, NPY_DOUBLE);
    default:
        return view(self->owner, (void *)v.species, 1, dims, NPY_INT);
    }
}

/* the getters of the state arrays: the closure says which */
static PyObject *get_state(SimObject *self, void *which) {
    return state_array(self, (int)(intptr_t)which);
}

/* sim.positions = x before the first step: a new simulation of the same configuration
 * from these positions (each particle keeping its species and diameter), checked as
 * init.positions is; refused, the simulation stays as it was. */
static int set_positions(SimObject *self, PyObject *value, void *c) {
    (void)c;
    if (!sim_ready(self)) return -1;
    if (!value) return PyErr_SetString(PyExc_TypeError, "positions cannot be deleted"), -1;
    if (hsbd_sim_equilibration_steps(self->sim) || hsbd_sim_production_steps(self->sim)) {
        PyErr_Format(hsbd_input_error,
                     "positions can be set only before the first step (%llu steps done); "
                     "build a new Simulation",
                     (unsigned long long)(hsbd_sim_equilibration_steps(self->sim) +
                                          hsbd_sim_production_steps(self->sim)));
        return -1;
    }
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    const npy_intp n = (npy_intp)cfg->system.n;
    const int d = p.rods ? 1 : (int)cfg->system.dimension;
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(value, NPY_DOUBLE, 1, 2,
                                                        NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
    if (!a) return -1;
    const npy_intp cols = PyArray_NDIM(a) == 1 ? 1 : PyArray_DIM(a, 1);
    if (PyArray_DIM(a, 0) != n || (cols != 3 && cols != d)) {
        PyErr_Format(hsbd_input_error,
                     "positions: an array of shape (%zd, 3)%s; got %zd rows of %zd values",
                     (Py_ssize_t)n,
                     d == 3   ? ""
                     : d == 2 ? " or (N, 2)"
                              : " or (N,)",
                     (Py_ssize_t)PyArray_DIM(a, 0), (Py_ssize_t)cols);
        Py_DECREF(a);
        return -1;
    }
    double *x = calloc(3 * (size_t)n, sizeof *x), *sigma = malloc((size_t)n * sizeof *sigma);
    int *species = malloc((size_t)n * sizeof *species);
    if (!x || !sigma || !species) {
        free(x), free(sigma), free(species), Py_DECREF(a);
        return PyErr_NoMemory(), -1;
    }
    const double *in = PyArray_DATA(a);
    for (npy_intp i = 0; i < n; ++i)
        for (npy_intp k = 0; k < cols && k < 3; ++k)
            x[3 * i + k] = in[i * cols + k];
    Py_DECREF(a);
    if (p.rods) {
        rods_fill(self);
        memcpy(species, self->species, (size_t)n * sizeof *species);
        memcpy(sigma, self->diameter, (size_t)n * sizeof *sigma);
    } else {
        const hsbd_spheres_view v = hsbd_spheres_get_view(p.spheres);
        memcpy(species, v.species, (size_t)n * sizeof *species);
        memcpy(sigma, v.sigma, (size_t)n * sizeof *sigma);
    }
    hsbd_error err;
    hsbd_sim *fresh;
    Py_BEGIN_ALLOW_THREADS fresh = hsbd_sim_alloc_from(cfg, x, species, sigma, &err);
    Py_END_ALLOW_THREADS free(x), free(sigma), free(species);
    if (!fresh) return raise_error(&err), -1;
    return sim_hold(self, fresh);
}

static PyObject *get_time(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    return PyFloat_FromDouble(p.rods ? hsbd_rods_get_view(p.rods).time
                                     : hsbd_spheres_get_view(p.spheres).time);
}

static PyObject *get_stage(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    static const char *const names[] = {"equilibrating", "producing", "done"};
    return PyUnicode_FromString(names[hsbd_sim_stage(self->sim)]);
}

static PyObject *get_steps(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    return Py_BuildValue("KK", (unsigned long long)hsbd_sim_equilibration_steps(self->sim),
                         (unsigned long long)hsbd_sim_production_steps(self->sim));
}

static PyObject *get_schedule(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    return Py_BuildValue("{s:d,s:d,s:K,s:K,s:N}", "dt", cfg->run.dt, "dt_equil",
                         hsbd_config_dt_equil(cfg), "equilibration_steps",
                         (unsigned long long)hsbd_config_equil_steps(cfg), "production_steps",
                         (unsigned long long)hsbd_config_steps(cfg), "replicas",
                         PyBool_FromLong(cfg->sample.blocking == HSBD_BLOCKS_REPLICAS));
}

static PyObject *get_model(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    return PyUnicode_FromString(p.rods ? "rods" : "spheres");
}

static PyObject *get_species_names(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    PyObject *t = PyTuple_New(cfg->species.n ? (Py_ssize_t)cfg->species.n : 1);
    for (size_t k = 0; t && k < (cfg->species.n ? cfg->species.n : 1); ++k) {
        PyObject *name = PyUnicode_FromString(cfg->species.n ? cfg->species.name[k] : "S");
        if (!name)
            Py_CLEAR(t);
        else
            PyTuple_SET_ITEM(t, (Py_ssize_t)k, name);
    }
    return t;
}

static PyObject *get_box(SimObject *self, void *c) {
    (void)c;
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    if (p.rods) return Py_BuildValue("(d)", hsbd_rods_get_view(p.rods).length);
    const hsbd_spheres_view v = hsbd_spheres_get_view(p.spheres);
    return v.dimension == 3 ? Py_BuildValue("(ddd)", v.box[0], v.box[1], v.box[2])
                            : Py_BuildValue("(dd)", v.box[0], v.box[1]);
}

/* ---- the observers' results (fresh arrays) ---- */

static PyObject *new_vector(npy_intp n, double **data) {
    PyObject *a = PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    if (a) *data = PyArray_DATA((PyArrayObject *)a);
    return a;
}

/* three new arrays of n doubles, returned as a tuple */
static PyObject *three_vectors(npy_intp n, double **a, double **b, double **c) {
    PyObject *x = new_vector(n, a), *y = new_vector(n, b), *z = new_vector(n, c);
    if (!x || !y || !z) {
        Py_XDECREF(x), Py_XDECREF(y), Py_XDECREF(z);
        return NULL;
    }
    return Py_BuildValue("NNN", x, y, z);
}

/* `species` (None, or an index or a name) as -1 (all) or an index; -2 and an exception
 * when there is no such species. One species: 0 and its name are everyone. */
static int species_index(const hsbd_config *cfg, PyObject *species, const char *what) {
    if (!species || species == Py_None) return -1;
    const size_t ns = cfg->species.n;
    if (PyUnicode_Check(species)) {
        const char *name = PyUnicode_AsUTF8(species);
        if (!name) return -2;
        for (size_t k = 0; k < ns; ++k)
            if (!strcmp(name, cfg->species.name[k])) return (int)k;
        if (!ns && !strcmp(name, "S")) return 0;
    } else {
        const long k = PyLong_AsLong(species);
        if (k == -1 && PyErr_Occurred()) return -2;
        if (k >= 0 && (size_t)k < (ns ? ns : 1)) return (int)k;
    }
    if (ns)
        PyErr_Format(hsbd_input_error, "%s(species=%R): the species are 0 .. %zu (%s%s%s)", what,
                     species, ns - 1, cfg->species.name[0], ns > 1 ? " .. " : "",
                     ns > 1 ? cfg->species.name[ns - 1] : "");
    else
        PyErr_Format(hsbd_input_error,
                     "%s(species=%R): this run has one species, 0 (or None: all particles)", what,
                     species);
    return -2;
}

/* the MSD accumulator of a species (-1: all); one species: all */
static const hsbd_msd *msd_of(const hsbd_sim_parts *p, int species) {
    return species < 0 || !p->msd_species[species] ? p->msd : p->msd_species[species];
}

static PyObject *lag_result(SimObject *self, PyObject *args, PyObject *kwargs, int fs) {
    static char *kw[] = {"species", NULL};
    PyObject *species = NULL;
    if (!sim_ready(self) ||
        !PyArg_ParseTupleAndKeywords(args, kwargs, fs ? "|O:fs" : "|O:msd", kw, &species))
        return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    const int k = species_index(cfg, species, fs ? "fs" : "msd");
    if (k < -1) return NULL;
    if (fs && p.rods)
        return PyErr_Format(hsbd_error_type, "fs(): disks and spheres only (sample.fs_k)"), NULL;
    const hsbd_msd *m = msd_of(&p, k);
    const size_t n = hsbd_msd_lags(m);
    double *t, *value, *err;
    PyObject *r = three_vectors((npy_intp)n, &t, &value, &err);
    if (!r) return NULL;
    /* spheres sample each coordinate: the MSD per particle is d times the result */
    const double d = p.spheres && !fs ? (double)cfg->system.dimension : 1.0;
    for (size_t j = 0; j < n; ++j) {
        size_t origins;
        hsbd_msd_result(m, j, &t[j], &value[j], &err[j], &origins);
        if (fs) hsbd_msd_fs(m, j, &value[j], &err[j]);
        value[j] *= d, err[j] *= d;
    }
    return r;
}

static PyObject *sim_msd(SimObject *self, PyObject *args, PyObject *kwargs) {
    return lag_result(self, args, kwargs, 0);
}

static PyObject *sim_fs(SimObject *self, PyObject *args, PyObject *kwargs) {
    return lag_result(self, args, kwargs, 1);
}

static PyObject *sim_d_long(SimObject *self, PyObject *args, PyObject *kwargs) {
    static char *kw[] = {"species", NULL};
    PyObject *species = NULL;
    if (!sim_ready(self) || !PyArg_ParseTupleAndKeywords(args, kwargs, "|O:d_long", kw, &species))
        return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    const int k = species_index(cfg, species, "d_long");
    if (k < -1) return NULL;
    if (p.rods)
        return PyErr_Format(hsbd_error_type,
                            "d_long(): disks and spheres only (rods in single file have no "
                            "long-time diffusion: see msd() and single_file_msd())"),
               NULL;
    double dl, err;
    hsbd_msd_long_time_diffusion(msd_of(&p, k), (int)cfg->system.dimension, &dl, &err);
    return Py_BuildValue("dd", dl, err);
}

/* the axis of `axis` (None: the field's axis, else the first with walls); -1 and an
 * exception when it has no profile */
static int profile_axis(const hsbd_config *cfg, const hsbd_sim_parts *p, PyObject *axis) {
    const int dim = (int)cfg->system.dimension;
    int a = -1;
    if (!axis || axis == Py_None) {
        for (int k = dim - 1; k >= 0; --k)
            if (p->slab[k]) a = k;
        if (cfg->field.type && p->slab[cfg->field.axis]) a = cfg->field.axis;
    } else if (PyUnicode_Check(axis)) {
        const char *s = PyUnicode_AsUTF8(axis);
        if (!s) return -1;
        a = s[0] && !s[1] && s[0] >= 'x' && s[0] < 'x' + dim ? s[0] - 'x' : -2;
    } else {
        const long k = PyLong_AsLong(axis);
        if (k == -1 && PyErr_Occurred()) return -1;
        a = k >= 0 && k < dim ? (int)k : -2;
    }
    if (a >= 0 && p->slab[a]) return a;
    char have[16] = "";
    for (int k = 0; k < dim; ++k)
        if (p->slab[k])
            snprintf(have + strlen(have), sizeof have - strlen(have), "%s'%c'", have[0] ? ", " : "",
                     "xyz"[k]);
    if (!have[0])
        PyErr_SetString(hsbd_error_type,
                        "density(): disks and spheres have profiles only along an axis with "
                        "walls (system.boundary) or the field (field.axis)");
    else
        PyErr_Format(hsbd_input_error, "density(axis=%R): the profiles are along %s",
                     axis ? axis : Py_None, have);
    return -1;
}

static PyObject *sim_density(SimObject *self, PyObject *args, PyObject *kwargs) {
    static char *kw[] = {"axis", "species", NULL};
    PyObject *axis = NULL, *species = NULL;
    if (!sim_ready(self) ||
        !PyArg_ParseTupleAndKeywords(args, kwargs, "|OO:density", kw, &axis, &species))
        return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    double *x, *value, *err;
    if (p.rods) {
        if ((axis && axis != Py_None) || (species && species != Py_None))
            return PyErr_Format(hsbd_input_error,
                                "density(): rods have one profile, of all rods along the line "
                                "(no axis or species)"),
                   NULL;
        PyObject *t = three_vectors((npy_intp)hsbd_profile_bins(p.profile), &x, &value, &err);
        if (t) hsbd_profile_density(p.profile, x, value, err);
        return t;
    }
    const int k = species_index(cfg, species, "density");
    if (k < -1) return NULL;
    const int a = profile_axis(cfg, &p, axis);
    if (a < 0) return NULL;
    PyObject *t = three_vectors((npy_intp)hsbd_slab_bins(p.slab[a]), &x, &value, &err);
    if (t) hsbd_slab_density(p.slab[a], cfg->species.n > 1 ? k : -1, x, value, err);
    return t;
}

static PyObject *sim_contact(SimObject *self, PyObject *unused) {
    (void)unused;
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    if (!p.profile) return PyErr_Format(hsbd_error_type, "contact(): rods only"), NULL;
    double *x, *value, *err;
    PyObject *t = three_vectors((npy_intp)hsbd_profile_bins(p.profile), &x, &value, &err);
    if (t) hsbd_profile_contact(p.profile, x, value, err);
    return t;
}

static PyObject *sim_gr(SimObject *self, PyObject *args, PyObject *kwargs) {
    static char *kw[] = {"pair", NULL};
    Py_ssize_t pair = 0;
    if (!sim_ready(self) || !PyArg_ParseTupleAndKeywords(args, kwargs, "|n:gr", kw, &pair))
        return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    if (!p.gr)
        return PyErr_Format(hsbd_error_type, "gr(): spheres with sample.gr_every > 0 only"), NULL;
    if (pair < 0 || (size_t)pair >= hsbd_gr_pairs(p.gr))
        return PyErr_Format(hsbd_input_error, "gr(pair=%zd): the pairs are 0 .. %zu (gr_pairs())",
                            pair, hsbd_gr_pairs(p.gr) - 1),
               NULL;
    double *r, *g, *err;
    PyObject *t = three_vectors((npy_intp)hsbd_gr_bins(p.gr), &r, &g, &err);
    if (t) hsbd_gr_result(p.gr, (size_t)pair, r, g, err);
    return t;
}

static PyObject *sim_gr_pairs(SimObject *self, PyObject *unused) {
    (void)unused;
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    PyObject *list = PyList_New(0);
    for (size_t k = 0; list && p.gr && k < hsbd_gr_pairs(p.gr); ++k) {
        size_t a, b;
        double value, err;
        hsbd_gr_pair_species(p.gr, k, &a, &b);
        hsbd_gr_contact(p.gr, k, &value, &err);
        PyObject *item = Py_BuildValue("{s:n,s:n,s:d,s:d}", "a", (Py_ssize_t)a, "b", (Py_ssize_t)b,
                                       "contact", value, "contact_err", err);
        if (!item || PyList_Append(list, item) != 0) Py_CLEAR(list);
        Py_XDECREF(item);
    }
    return list;
}

static PyObject *sim_summary_json(SimObject *self, PyObject *unused) {
    (void)unused;
    if (!sim_ready(self)) return NULL;
    char *json;
    hsbd_error err;
    if (hsbd_sim_summary(self->sim, &json, &err) != HSBD_OK) return raise_error(&err);
    PyObject *s = PyUnicode_FromString(json);
    free(json);
    return s;
}

static PyMethodDef sim_methods[] = {
    {"step", (PyCFunction)(void (*)(void))sim_step, METH_VARARGS | METH_KEYWORDS,
     "step($self, /, n=1)\n--\n\n"
     "n more steps of the run (equilibration first, then production with its sampling); "
     "fewer when the run ends. n >= 0 (InputError otherwise)."},
    {"density", (PyCFunction)(void (*)(void))sim_density, METH_VARARGS | METH_KEYWORDS,
     "density($self, /, axis=None, species=None)\n--\n\n"
     "The density profile so far as (x, rho, err), bin centres, number density and its "
     "block error. Rods: along the line (per length, mean N/L; no axis or species). Disks "
     "and spheres: per volume along an axis with walls or the field (axis 0-2 or 'x', 'y', "
     "'z'; None: the field's axis, else the first with walls), of all particles or of one "
     "species (index or name)."},
    {"contact", (PyCFunction)sim_contact, METH_NOARGS,
     "contact($self, /)\n--\n\n"
     "Rods: the contact density rho2(x, x + sigma) so far as (x, rho2, err), x the left "
     "rod (the default estimator of contact.tsv)."},
    {"msd", (PyCFunction)(void (*)(void))sim_msd, METH_VARARGS | METH_KEYWORDS,
     "msd($self, /, species=None)\n--\n\n"
     "The mean-squared displacement per particle so far as (t, msd, err): lag times, MSD "
     "(disks and spheres: summed over the d coordinates) and its block error; all "
     "particles (None) or one species (index or name)."},
    {"fs", (PyCFunction)(void (*)(void))sim_fs, METH_VARARGS | METH_KEYWORDS,
     "fs($self, /, species=None)\n--\n\n"
     "Disks and spheres: the self-intermediate scattering function F_s(k, t) at "
     "k = sample.fs_k (along each axis, averaged) so far as (t, fs, err); all particles "
     "(None) or one species."},
    {"d_long", (PyCFunction)(void (*)(void))sim_d_long, METH_VARARGS | METH_KEYWORDS,
     "d_long($self, /, species=None)\n--\n\n"
     "Disks and spheres: the long-time self-diffusion coefficient D_L so far as "
     "(D_L, err), from the MSD's slope between its largest lag and a tenth of it (as "
     "summary.json's D_long); NaN while there are too few lags."},
    {"gr", (PyCFunction)(void (*)(void))sim_gr, METH_VARARGS | METH_KEYWORDS,
     "gr($self, /, pair=0)\n--\n\n"
     "Disks and spheres (sample.gr_every > 0): g(r) of a species pair so far as "
     "(r, g, err); the pairs are those of gr_pairs()."},
    {"gr_pairs", (PyCFunction)sim_gr_pairs, METH_NOARGS,
     "gr_pairs($self, /)\n--\n\n"
     "The species pairs of gr() as [{'a', 'b', 'contact', 'contact_err'}], with their "
     "contact values g(sigma_ab+)."},
    {"summary_json", (PyCFunction)sim_summary_json, METH_NOARGS,
     "summary_json($self, /)\n--\n\n"
     "The results so far as the text of summary.json (summary() parses it)."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef sim_getset[] = {
    {"positions", (getter)get_state, (setter)set_positions,
     "(N, 3) float64 read-only view of the wrapped positions (rods: x in [0, L) with "
     "y = z = 0), showing the state after each step. Settable before the first step: an "
     "(N, 3) array (disks (N, 2), rods (N,)) replaces the initial state, each particle "
     "keeping its species and diameter, checked as init.positions is (overlaps, walls); "
     "rods are then renumbered in line order.",
     (void *)(intptr_t)ARRAY_POSITIONS},
    {"images", (getter)get_state, NULL,
     "(N, 3) int64 read-only view: box crossings (unwrapped = positions + images * box).",
     (void *)(intptr_t)ARRAY_IMAGES},
    {"diameters", (getter)get_state, NULL, "(N,) float64 read-only view: sigma of each particle.",
     (void *)(intptr_t)ARRAY_DIAMETERS},
    {"species", (getter)get_state, NULL,
     "(N,) int read-only view: species indices (into species_names).",
     (void *)(intptr_t)ARRAY_SPECIES},
    {"time", (getter)get_time, NULL,
     "Simulated time since the start, equilibration included: production begins at "
     "t_equil (rods: its steps at run.dt_equil when set) and ends at t_equil + t_total "
     "(sample.blocking = replicas: each block's equilibration adds to it).",
     NULL},
    {"stage", (getter)get_stage, NULL, "'equilibrating', 'producing' or 'done'.", NULL},
    {"steps", (getter)get_steps, NULL, "(equilibration steps, production steps) done so far.",
     NULL},
    {"schedule", (getter)get_schedule, NULL,
     "The run's plan: {'dt', 'dt_equil', 'equilibration_steps' (of each equilibration), "
     "'production_steps', 'replicas' (sample.blocking = replicas: an equilibration before "
     "each block)}.",
     NULL},
    {"model", (getter)get_model, NULL, "'rods' or 'spheres' (disks too).", NULL},
    {"species_names", (getter)get_species_names, NULL,
     "The species' names by index (one species: ('S',)).", NULL},
    {"box", (getter)get_box, NULL, "Box lengths (rods: (L,)).", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject SimType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hsbd._hsbd.Simulation",
    .tp_basicsize = sizeof(SimObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "The C type under hsbd.Simulation (see its documentation).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)sim_init,
    .tp_dealloc = (destructor)sim_dealloc,
    .tp_methods = sim_methods,
    .tp_getset = sim_getset,
};

/* ---- module functions: runs and theory ---- */

static PyObject *mod_run(PyObject *mod, PyObject *args, PyObject *kwargs) {
    (void)mod;
    PyObject *config = NULL, *out = NULL, *force = Py_False, *sections = NULL;
    /* out and force are keywords of run(); the other keywords are sections */
    if (!PyArg_ParseTuple(args, "|O:run", &config)) return NULL;
    if (kwargs) {
        sections = PyDict_Copy(kwargs);
        if (!sections) return NULL;
        out = PyDict_GetItemString(sections, "out");
        Py_XINCREF(out);
        PyObject *f = PyDict_GetItemString(sections, "force");
        if (f) force = f;
        Py_INCREF(force);
        PyDict_DelItemString(sections, "out"), PyErr_Clear();
        PyDict_DelItemString(sections, "force"), PyErr_Clear();
    } else {
        Py_INCREF(force);
    }
    built_config b = {0};
    PyObject *result = NULL;
    if (build_config(config, sections, &b) != 0) goto done;
    if (out && out != Py_None) {
        PyObject *dir = PyOS_FSPath(out);
        PyObject *value = dir && PyUnicode_Check(dir) ? Py_NewRef(dir) : NULL;
        if (dir && !value) PyErr_SetString(PyExc_TypeError, "run(): out is a path (str)");
        Py_XDECREF(dir);
        const int rc =
            value ? assign(&b.cfg, &b.sets, "output.dir", value, "Python (run(out=...))") : -1;
        Py_XDECREF(value);
        if (rc != 0) goto done;
    }
    if (!b.cfg.output.dir[0]) {
        PyErr_SetString(hsbd_input_error, "run(): give the run directory, out=DIR (or output.dir)");
        goto done;
    }
    if (finalize_config(&b) != 0) goto done;
    const hsbd_run_source source = {.name = b.path,
                                    .text = b.text ? b.text : "",
                                    .text_len = b.text ? b.text_len : 0,
                                    .sets = (const char *const *)b.sets.text,
                                    .nsets = b.sets.n};
    const hsbd_run_options opt = {.force = PyObject_IsTrue(force) == 1, .source = &source};
    hsbd_error err;
    int rc;
    Py_BEGIN_ALLOW_THREADS rc = hsbd_run(&b.cfg, &opt, &err);
    Py_END_ALLOW_THREADS if (rc != HSBD_OK) raise_error(&err);
    else result = PyUnicode_FromString(b.cfg.output.dir);
done:
    built_config_free(&b);
    Py_XDECREF(sections);
    Py_XDECREF(out);
    Py_DECREF(force);
    return result;
}

static PyObject *mod_percus(PyObject *mod, PyObject *args, PyObject *kwargs) {
    (void)mod;
    static char *kw[] = {"sigma", "rho", "amplitude", "wavelength", "gamma", "points", NULL};
    hsbd_percus_params p = {.wavelength = 1.0, .points = 2000};
    Py_ssize_t points = 2000;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "ddd|ddn:percus", kw, &p.sigma, &p.rho_mean,
                                     &p.amplitude, &p.wavelength, &p.gamma, &points))
        return NULL;
    if (points < 2) return PyErr_Format(hsbd_input_error, "percus: points = %zd < 2", points), NULL;
    p.points = (size_t)points;
    hsbd_percus_result r;
    hsbd_error err;
    int rc;
    Py_BEGIN_ALLOW_THREADS rc = hsbd_percus_solve(&p, &r, &err);
    Py_END_ALLOW_THREADS if (rc != HSBD_OK) return raise_error(&err);
    double *x, *rho, *rho2;
    PyObject *t = three_vectors((npy_intp)r.m, &x, &rho, &rho2);
    if (t) {
        memcpy(x, r.x, r.m * sizeof *x);
        memcpy(rho, r.rho, r.m * sizeof *rho);
        memcpy(rho2, r.rho2, r.m * sizeof *rho2);
    }
    hsbd_percus_result_free(&r);
    return t;
}

/* Packing fractions of the equations of state: 0 <= phi < close packing (spheres: fcc,
 * pi / sqrt(18); disks: hexagonal, pi / sqrt(12)), where they describe a system. */
#define CLOSE_PACKING_3D 0.74048048969306104 /* pi / sqrt(18) */
#define CLOSE_PACKING_2D 0.90689968211710892 /* pi / sqrt(12) */

static int packing_fraction(PyObject *arg, double close, const char *name, double *phi) {
    *phi = PyFloat_AsDouble(arg);
    if (*phi == -1.0 && PyErr_Occurred()) return -1;
    if (*phi >= 0 && *phi < close) return 0;
    char msg[200];
    snprintf(msg, sizeof msg,
             "%s(phi): phi = %.17g is outside 0 <= phi < %.6f (close packing of hard %s)", name,
             *phi, close, close == CLOSE_PACKING_3D ? "spheres" : "disks");
    PyErr_SetString(hsbd_input_error, msg);
    return -1;
}

#define EQUATION_OF_STATE(name, fn, close)                                                         \
    static PyObject *mod_##name(PyObject *mod, PyObject *arg) {                                    \
        (void)mod;                                                                                 \
        double phi;                                                                                \
        if (packing_fraction(arg, close, #name, &phi) != 0) return NULL;                           \
        return PyFloat_FromDouble(fn(phi));                                                        \
    }
EQUATION_OF_STATE(hs_z_cs, hsbd_hs_z_cs, CLOSE_PACKING_3D)
EQUATION_OF_STATE(hs_contact_cs, hsbd_hs_contact_cs, CLOSE_PACKING_3D)
EQUATION_OF_STATE(hd_z_henderson, hsbd_hd_z_henderson, CLOSE_PACKING_2D)
EQUATION_OF_STATE(hd_contact_henderson, hsbd_hd_contact_henderson, CLOSE_PACKING_2D)

/* hard rods: rho >= 0, sigma >= 0, rho sigma < 1 (the line not filled) */
static int rods_density(const char *name, double rho, double sigma) {
    if (rho >= 0 && sigma >= 0 && rho * sigma < 1) return 0;
    char msg[256];
    snprintf(msg, sizeof msg,
             "%s: rho = %.17g, sigma = %.17g; allowed: rho >= 0, sigma >= 0, rho sigma < 1", name,
             rho, sigma);
    PyErr_SetString(hsbd_input_error, msg);
    return -1;
}

#define TONKS(name, fn)                                                                            \
    static PyObject *mod_##name(PyObject *mod, PyObject *args, PyObject *kwargs) {                 \
        (void)mod;                                                                                 \
        static char *kw[] = {"rho", "sigma", NULL};                                                \
        double rho, sigma;                                                                         \
        if (!PyArg_ParseTupleAndKeywords(args, kwargs, "dd:" #name, kw, &rho, &sigma) ||           \
            rods_density(#name, rho, sigma) != 0)                                                  \
            return NULL;                                                                           \
        return PyFloat_FromDouble(fn(rho, sigma));                                                 \
    }
TONKS(tonks_pressure, hsbd_tonks_pressure)
TONKS(tonks_contact, hsbd_tonks_contact)

static PyObject *mod_single_file_msd(PyObject *mod, PyObject *args, PyObject *kwargs) {
    (void)mod;
    static char *kw[] = {"t", "rho", "sigma", "D", NULL};
    PyObject *times;
    double rho, sigma, d = 1.0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "Odd|d:single_file_msd", kw, &times, &rho,
                                     &sigma, &d) ||
        rods_density("single_file_msd", rho, sigma) != 0)
        return NULL;
    if (!(rho > 0) || !(d > 0) || !isfinite(d)) {
        char msg[160];
        snprintf(msg, sizeof msg,
                 "single_file_msd: rho = %.17g, D = %.17g; allowed: rho > 0, D > 0", rho, d);
        PyErr_SetString(hsbd_input_error, msg);
        return NULL;
    }
    PyArrayObject *t = (PyArrayObject *)PyArray_FROMANY(times, NPY_DOUBLE, 0, 0,
                                                        NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED);
    if (!t) return NULL;
    PyArrayObject *out = (PyArrayObject *)PyArray_NewLikeArray(t, NPY_CORDER, NULL, 0);
    if (out) {
        const double *in = PyArray_DATA(t);
        double *o = PyArray_DATA(out);
        const npy_intp n = PyArray_SIZE(t);
        Py_BEGIN_ALLOW_THREADS for (npy_intp k = 0; k < n; ++k) o[k] =
            hsbd_single_file_msd_exact(in[k], rho, sigma, d);
        Py_END_ALLOW_THREADS
    }
    Py_DECREF(t);
    return PyArray_Return(out);
}

static PyObject *mod_version(PyObject *mod, PyObject *unused) {
    (void)mod, (void)unused;
    return PyUnicode_FromString(hsbd_version());
}

static PyMethodDef module_methods[] = {
    {"run", (PyCFunction)(void (*)(void))mod_run, METH_VARARGS | METH_KEYWORDS,
     "run(config=None, /, *, out=None, force=False, **sections)\n--\n\n"
     "Run a whole configuration into the directory out exactly as `hsbd run` does "
     "(tables, summary.json, trajectory, checkpoints that `hsbd resume` continues) and "
     "return the directory; config and sections as for Simulation. force=True replaces a "
     "finished run's directory. hsbd.load(out) reads it."},
    {"percus", (PyCFunction)(void (*)(void))mod_percus, METH_VARARGS | METH_KEYWORDS,
     "percus(sigma, rho, amplitude, wavelength=1, gamma=0, points=2000)\n--\n\n"
     "Percus' exact density of hard rods of length sigma and mean density rho in "
     "U(x) = (amplitude/2) cos(2 pi x / wavelength) (kT units) over one period, and the "
     "contact density, as (x, rho, rho2)."},
    {"tonks_pressure", (PyCFunction)(void (*)(void))mod_tonks_pressure,
     METH_VARARGS | METH_KEYWORDS,
     "tonks_pressure(rho, sigma)\n--\n\n"
     "Hard rods (Tonks): beta P = rho / (1 - rho sigma); rho sigma < 1."},
    {"tonks_contact", (PyCFunction)(void (*)(void))mod_tonks_contact, METH_VARARGS | METH_KEYWORDS,
     "tonks_contact(rho, sigma)\n--\n\n"
     "Hard rods (Tonks): the contact density rho2(x, x + sigma) = rho^2 / (1 - rho sigma)."},
    {"hs_z_cs", mod_hs_z_cs, METH_O,
     "hs_z_cs(phi, /)\n--\n\n"
     "Hard spheres: the Carnahan-Starling compressibility factor "
     "Z = (1 + phi + phi^2 - phi^3) / (1 - phi)^3 at packing fraction 0 <= phi < pi/sqrt(18) "
     "(the fluid's; beyond freezing, 0.494, the metastable branch)."},
    {"hs_contact_cs", mod_hs_contact_cs, METH_O,
     "hs_contact_cs(phi, /)\n--\n\n"
     "Hard spheres: Carnahan-Starling's contact value g(sigma+) = (1 - phi/2) / (1 - phi)^3, "
     "0 <= phi < pi/sqrt(18)."},
    {"hd_z_henderson", mod_hd_z_henderson, METH_O,
     "hd_z_henderson(phi, /)\n--\n\n"
     "Hard disks: Henderson's compressibility factor Z = (1 + phi^2/8) / (1 - phi)^2, "
     "0 <= phi < pi/sqrt(12)."},
    {"hd_contact_henderson", mod_hd_contact_henderson, METH_O,
     "hd_contact_henderson(phi, /)\n--\n\n"
     "Hard disks: Henderson's contact value g(sigma+) = (1 - 7 phi/16) / (1 - phi)^2, "
     "0 <= phi < pi/sqrt(12)."},
    {"single_file_msd", (PyCFunction)(void (*)(void))mod_single_file_msd,
     METH_VARARGS | METH_KEYWORDS,
     "single_file_msd(t, rho, sigma, D=1)\n--\n\n"
     "The exact tagged MSD of field-free hard rods on a line (single file) at times t "
     "(array): from 2 D t at short times to ((1 - rho sigma) / rho) sqrt(4 D t / pi)."},
    {"version", mod_version, METH_NOARGS,
     "version()\n--\n\n"
     "The library's version and git commit, 'MAJOR.MINOR.PATCH (git COMMIT)'."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT,
    "hsbd._hsbd",
    "The C half of the package hsbd (import hsbd; docs/python.md).",
    -1,
    module_methods,
    NULL,
    NULL,
    NULL,
    NULL};

PyMODINIT_FUNC PyInit__hsbd(void);
PyMODINIT_FUNC PyInit__hsbd(void) {
    import_array();
    if (PyType_Ready(&SimType) < 0) return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (!m) return NULL;
    hsbd_error_type = PyErr_NewExceptionWithDoc(
        "hsbd.Error", "A run failed (hsbd's error message).", PyExc_RuntimeError, NULL);
    PyObject *bases = hsbd_error_type ? PyTuple_Pack(2, hsbd_error_type, PyExc_ValueError) : NULL;
    hsbd_input_error =
        bases ? PyErr_NewExceptionWithDoc("hsbd.InputError",
                                          "Bad input: the message `hsbd run` prints, naming the "
                                          "file and line or the key, and the allowed range.",
                                          bases, NULL)
              : NULL;
    Py_XDECREF(bases);
    if (!hsbd_input_error || PyModule_AddObjectRef(m, "Error", hsbd_error_type) < 0 ||
        PyModule_AddObjectRef(m, "InputError", hsbd_input_error) < 0 ||
        PyModule_AddObjectRef(m, "Simulation", (PyObject *)&SimType) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
