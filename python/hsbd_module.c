/* The Python module `hsbd`: a CPython extension over the public C API (libhsbd.so).
 * Simulations built from a configuration file, a dict or keyword arguments (the schema of
 * docs/config.md), stepped from Python, with the state as read-only numpy views and the
 * observers' results; the exact theory; runs written as `hsbd run` writes them.
 * Documentation: docs/python.md. */
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

typedef struct {
    PyObject_HEAD hsbd_sim *sim;
    /* rods: positions, images and diameters are computed into these at each access */
    double *x, *diameter;
    int64_t *image;
    int *species; /* rods of one species: zeros */
} SimObject;

static void sim_dealloc(SimObject *self) {
    hsbd_sim_free(self->sim);
    free(self->x);
    free(self->diameter);
    free(self->image);
    free(self->species);
    Py_TYPE(self)->tp_free((PyObject *)self);
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
    hsbd_sim_free(self->sim); /* __init__ called again: a new simulation */
    free(self->x), free(self->diameter), free(self->image), free(self->species);
    self->x = self->diameter = NULL, self->image = NULL, self->species = NULL;
    Py_BEGIN_ALLOW_THREADS self->sim = hsbd_sim_alloc(&b.cfg, &err);
    Py_END_ALLOW_THREADS built_config_free(&b);
    if (!self->sim) return raise_error(&err), -1;
    const size_t n = (size_t)hsbd_sim_config(self->sim)->system.n;
    if (hsbd_sim_get_parts(self->sim).rods) {
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

static PyObject *advance(SimObject *self, uint64_t steps) {
    hsbd_error err;
    int rc;
    Py_BEGIN_ALLOW_THREADS rc = hsbd_sim_advance(self->sim, steps, &err);
    Py_END_ALLOW_THREADS if (rc != HSBD_OK) return raise_error(&err);
    Py_RETURN_NONE;
}

static PyObject *sim_step(SimObject *self, PyObject *args) {
    unsigned long long n = 1;
    if (!sim_ready(self) || !PyArg_ParseTuple(args, "|K:step", &n)) return NULL;
    return advance(self, n);
}

static PyObject *sim_run(SimObject *self, PyObject *args) {
    double t;
    if (!sim_ready(self) || !PyArg_ParseTuple(args, "d:run", &t)) return NULL;
    const double dt = hsbd_sim_config(self->sim)->run.dt;
    if (!(t >= 0) || !isfinite(t)) {
        PyErr_Format(hsbd_input_error, "run(t): t = %R must be finite and >= 0",
                     PyTuple_GET_ITEM(args, 0));
        return NULL;
    }
    return advance(self, (uint64_t)llround(t / dt));
}

/* A read-only array over memory the simulation owns; the array keeps it alive. */
static PyObject *view(SimObject *self, void *data, int nd, npy_intp *dims, int type) {
    PyObject *a = PyArray_SimpleNewFromData(nd, dims, type, data);
    if (!a) return NULL;
    PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
    Py_INCREF(self);
    if (PyArray_SetBaseObject((PyArrayObject *)a, (PyObject *)self) != 0) {
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
    if (p.rods) {
        rods_fill(self);
        switch (which) {
        case ARRAY_POSITIONS:
            return view(self, self->x, 2, dims, NPY_DOUBLE);
        case ARRAY_IMAGES:
            return view(self, self->image, 2, dims, NPY_INT64);
        case ARRAY_DIAMETERS:
            return view(self, self->diameter, 1, dims, NPY_DOUBLE);
        default:
            return view(self, self->species, 1, dims, NPY_INT);
        }
    }
    const hsbd_spheres_view v = hsbd_spheres_get_view(p.spheres);
    switch (which) {
    case ARRAY_POSITIONS:
        return view(self, (void *)v.x, 2, dims, NPY_DOUBLE);
    case ARRAY_IMAGES:
        return view(self, (void *)v.image, 2, dims, NPY_INT64);
    case ARRAY_DIAMETERS:
        return view(self, (void *)v.sigma, 1, dims, NPY_DOUBLE);
    default:
        return view(self, (void *)v.species, 1, dims, NPY_INT);
    }
}

/* the getters of the state arrays: the closure says which */
static PyObject *get_state(SimObject *self, void *which) {
    return state_array(self, (int)(intptr_t)which);
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

/* rods: the density profile (contact = 0) or the contact density (1) so far */
static PyObject *profile_result(SimObject *self, int contact) {
    if (!sim_ready(self)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    if (!p.profile)
        return PyErr_Format(hsbd_error_type, "%s(): rods only", contact ? "contact" : "density"),
               NULL;
    double *x, *value, *err;
    PyObject *t = three_vectors((npy_intp)hsbd_profile_bins(p.profile), &x, &value, &err);
    if (t) (contact ? hsbd_profile_contact : hsbd_profile_density)(p.profile, x, value, err);
    return t;
}

static PyObject *sim_density(SimObject *self, PyObject *unused) {
    (void)unused;
    return profile_result(self, 0);
}

static PyObject *sim_contact(SimObject *self, PyObject *unused) {
    (void)unused;
    return profile_result(self, 1);
}

static PyObject *sim_msd(SimObject *self, PyObject *args, PyObject *kwargs) {
    static char *kw[] = {"species", NULL};
    int species = -1;
    if (!sim_ready(self) || !PyArg_ParseTupleAndKeywords(args, kwargs, "|i:msd", kw, &species))
        return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    const hsbd_config *cfg = hsbd_sim_config(self->sim);
    if (species >= (int)cfg->species.n || species < -1 || (species >= 0 && !p.msd_species[species]))
        return PyErr_Format(hsbd_input_error, "msd(species=%d): the species are 0 .. %d", species,
                            (int)cfg->species.n - 1),
               NULL;
    const hsbd_msd *m = species < 0 ? p.msd : p.msd_species[species];
    const size_t n = hsbd_msd_lags(m);
    double *t, *msd, *err;
    PyObject *r = three_vectors((npy_intp)n, &t, &msd, &err);
    if (!r) return NULL;
    /* spheres sample each coordinate: the MSD per particle is d times the result */
    const double d = p.spheres ? (double)cfg->system.dimension : 1.0;
    for (size_t k = 0; k < n; ++k) {
        size_t origins;
        hsbd_msd_result(m, k, &t[k], &msd[k], &err[k], &origins);
        msd[k] *= d, err[k] *= d;
    }
    return r;
}

static PyObject *sim_gr(SimObject *self, PyObject *args) {
    Py_ssize_t pair = 0;
    if (!sim_ready(self) || !PyArg_ParseTuple(args, "|n:gr", &pair)) return NULL;
    const hsbd_sim_parts p = hsbd_sim_get_parts(self->sim);
    if (!p.gr)
        return PyErr_Format(hsbd_error_type, "gr(): spheres with sample.gr_every > 0 only"), NULL;
    if (pair < 0 || (size_t)pair >= hsbd_gr_pairs(p.gr))
        return PyErr_Format(hsbd_input_error, "gr(pair=%zd): the pairs are 0 .. %zu", pair,
                            hsbd_gr_pairs(p.gr) - 1),
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

static PyMethodDef sim_methods[] = {
    {"step", (PyCFunction)sim_step, METH_VARARGS,
     "step(n=1): n more steps of the run (equilibration first, then production with its "
     "sampling); fewer when the run ends."},
    {"run", (PyCFunction)sim_run, METH_VARARGS, "run(t): round(t / run.dt) more steps."},
    {"density", (PyCFunction)sim_density, METH_NOARGS,
     "density() -> (x, rho, err): the density profile so far (rods)."},
    {"contact", (PyCFunction)sim_contact, METH_NOARGS,
     "contact() -> (x, rho2, err): the contact density rho2(x, x + sigma) so far (rods)."},
    {"msd", (PyCFunction)(void (*)(void))sim_msd, METH_VARARGS | METH_KEYWORDS,
     "msd(species=None) -> (t, msd, err): mean-squared displacement per particle so far."},
    {"gr", (PyCFunction)sim_gr, METH_VARARGS,
     "gr(pair=0) -> (r, g, err): g(r) of a species pair so far (spheres)."},
    {"gr_pairs", (PyCFunction)sim_gr_pairs, METH_NOARGS,
     "gr_pairs() -> [{'a', 'b', 'contact', 'contact_err'}]: the pairs and their contact "
     "values g(sigma_ab+)."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef sim_getset[] = {
    {"positions", (getter)get_state, NULL,
     "(N, 3) float64, read-only view of the wrapped positions (rods: x in [0, L) with "
     "y = z = 0); valid until the next step.",
     (void *)(intptr_t)ARRAY_POSITIONS},
    {"images", (getter)get_state, NULL,
     "(N, 3) int64 read-only view: box crossings; valid until the next step.",
     (void *)(intptr_t)ARRAY_IMAGES},
    {"diameters", (getter)get_state, NULL, "(N,) float64 read-only view: sigma.",
     (void *)(intptr_t)ARRAY_DIAMETERS},
    {"species", (getter)get_state, NULL, "(N,) int read-only view: species indices.",
     (void *)(intptr_t)ARRAY_SPECIES},
    {"time", (getter)get_time, NULL, "simulated time (restarts at 0 for production)", NULL},
    {"stage", (getter)get_stage, NULL, "'equilibrating', 'producing' or 'done'", NULL},
    {"steps", (getter)get_steps, NULL, "(equilibration steps, production steps) done", NULL},
    {"box", (getter)get_box, NULL, "box lengths (rods: (L,))", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject SimType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hsbd.Simulation",
    .tp_basicsize = sizeof(SimObject),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Simulation(config=None, **sections): rods or spheres built as `hsbd run` "
              "builds them from a configuration file (path), a dict ({'system.N': 50} or "
              "{'system': {'N': 50}}) and/or sections as keywords (system={'N': 50}). Bad "
              "input raises hsbd.InputError with the message hsbd run prints.",
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
        PyObject *dir = PyObject_Str(out);
        const char *d = dir ? PyUnicode_AsUTF8(dir) : NULL;
        if (!d) {
            Py_XDECREF(dir);
            goto done;
        }
        PyObject *text = PyUnicode_FromFormat("output.dir=%s", d);
        Py_DECREF(dir);
        PyObject *value =
            text ? PyUnicode_FromString(strchr(PyUnicode_AsUTF8(text), '=') + 1) : NULL;
        Py_XDECREF(text);
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

typedef double (*closed_form)(double);
typedef double (*closed_form2)(double, double);

#define ONE_ARG(name, fn, doc)                                                                     \
    static PyObject *mod_##name(PyObject *mod, PyObject *arg) {                                    \
        (void)mod;                                                                                 \
        const double v = PyFloat_AsDouble(arg);                                                    \
        if (v == -1.0 && PyErr_Occurred()) return NULL;                                            \
        return PyFloat_FromDouble(fn(v));                                                          \
    }
#define TWO_ARGS(name, fn)                                                                         \
    static PyObject *mod_##name(PyObject *mod, PyObject *args) {                                   \
        (void)mod;                                                                                 \
        double a, b;                                                                               \
        if (!PyArg_ParseTuple(args, "dd:" #name, &a, &b)) return NULL;                             \
        return PyFloat_FromDouble(fn(a, b));                                                       \
    }

ONE_ARG(hs_z_cs, hsbd_hs_z_cs, "")
ONE_ARG(hs_contact_cs, hsbd_hs_contact_cs, "")
ONE_ARG(hd_z_henderson, hsbd_hd_z_henderson, "")
ONE_ARG(hd_contact_henderson, hsbd_hd_contact_henderson, "")
TWO_ARGS(tonks_pressure, hsbd_tonks_pressure)
TWO_ARGS(tonks_contact, hsbd_tonks_contact)

static PyObject *mod_single_file_msd(PyObject *mod, PyObject *args, PyObject *kwargs) {
    (void)mod;
    static char *kw[] = {"t", "rho", "sigma", "D", NULL};
    PyObject *times;
    double rho, sigma, d = 1.0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "Odd|d:single_file_msd", kw, &times, &rho,
                                     &sigma, &d))
        return NULL;
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
     "run(config=None, out=None, force=False, **sections) -> the run directory: the whole "
     "run written exactly as `hsbd run` writes it (tables, summary.json, trajectory, "
     "checkpoints that `hsbd resume` continues)."},
    {"percus", (PyCFunction)(void (*)(void))mod_percus, METH_VARARGS | METH_KEYWORDS,
     "percus(sigma, rho, amplitude, wavelength=1, gamma=0, points=2000) -> (x, rho, rho2): "
     "Percus' exact density of hard rods of length sigma and mean density rho in "
     "U(x) = (amplitude/2) cos(2 pi x / wavelength) (kT units) over one period, and the "
     "contact density."},
    {"tonks_pressure", mod_tonks_pressure, METH_VARARGS,
     "tonks_pressure(rho, sigma): beta P = rho / (1 - rho sigma)"},
    {"tonks_contact", mod_tonks_contact, METH_VARARGS,
     "tonks_contact(rho, sigma): contact density rho2(x, x + sigma) = rho^2 / (1 - rho sigma)"},
    {"hs_z_cs", mod_hs_z_cs, METH_O, "hs_z_cs(phi): Carnahan-Starling compressibility factor"},
    {"hs_contact_cs", mod_hs_contact_cs, METH_O,
     "hs_contact_cs(phi): Carnahan-Starling g(sigma+) = (1 - phi/2) / (1 - phi)^3"},
    {"hd_z_henderson", mod_hd_z_henderson, METH_O,
     "hd_z_henderson(phi): hard disks, Henderson's compressibility factor"},
    {"hd_contact_henderson", mod_hd_contact_henderson, METH_O,
     "hd_contact_henderson(phi): hard disks, Henderson's g(sigma+)"},
    {"single_file_msd", (PyCFunction)(void (*)(void))mod_single_file_msd,
     METH_VARARGS | METH_KEYWORDS,
     "single_file_msd(t, rho, sigma, D=1): the exact tagged MSD of field-free hard rods "
     "(single file) at times t (array), from 2 D t to ((1 - rho sigma) / rho) sqrt(4 D t / "
     "pi)."},
    {"version", mod_version, METH_NOARGS, "version(): the linked libhsbd's version"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT,
    "hsbd",
    "Brownian dynamics of hard rods, disks and spheres (docs/python.md).",
    -1,
    module_methods,
    NULL,
    NULL,
    NULL,
    NULL};

PyMODINIT_FUNC PyInit_hsbd(void);
PyMODINIT_FUNC PyInit_hsbd(void) {
    import_array();
    if (PyType_Ready(&SimType) < 0) return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (!m) return NULL;
    hsbd_error_type = PyErr_NewException("hsbd.Error", PyExc_RuntimeError, NULL);
    PyObject *bases = hsbd_error_type ? PyTuple_Pack(2, hsbd_error_type, PyExc_ValueError) : NULL;
    hsbd_input_error = bases ? PyErr_NewException("hsbd.InputError", bases, NULL) : NULL;
    Py_XDECREF(bases);
    if (!hsbd_input_error || PyModule_AddObjectRef(m, "Error", hsbd_error_type) < 0 ||
        PyModule_AddObjectRef(m, "InputError", hsbd_input_error) < 0 ||
        PyModule_AddObjectRef(m, "Simulation", (PyObject *)&SimType) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
