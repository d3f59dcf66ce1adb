/* Where each key got its value: a small record per key (its kind, a file's line, its text
 * among the configuration's distinct texts), formatted into a ring of buffers when asked,
 * so that messages name "file:line", "<origin> section.key" or the derived default. */
#include "config/schema.h"

#include <string.h>

/* hsbd_key_origin.kind; 0 (what hsbd_config_defaults' memset leaves) is the default */
enum { ORIGIN_DEFAULT = 0, ORIGIN_FILE, ORIGIN_SET, ORIGIN_DERIVED, ORIGIN_INPUT };

/* Where `text` (cut to HSBD_ORIGIN_MAX - 1 characters, like the origins it makes) starts
 * among the texts, held once. The pool's last byte stays NUL: a text beyond the pool's room
 * is cut to what is left, down to that empty text. */
static uint16_t text_offset(hsbd_origins *o, const char *text) {
    const size_t len = strnlen(text, HSBD_ORIGIN_MAX - 1);
    for (size_t at = 0; at < o->texts_used; at += strlen(o->texts + at) + 1)
        if (strlen(o->texts + at) == len && !memcmp(o->texts + at, text, len)) return (uint16_t)at;
    const size_t room = HSBD_ORIGIN_TEXTS - 1 - (size_t)o->texts_used;
    if (room == 0) return HSBD_ORIGIN_TEXTS - 1;
    const size_t kept = len < room - 1 ? len : room - 1;
    const uint16_t at = o->texts_used;
    memcpy(o->texts + at, text, kept);
    o->texts[at + kept] = '\0';
    o->texts_used = (uint16_t)(at + kept + 1);
    return at;
}

static void record(hsbd_config *cfg, const key_spec *k, int kind, const char *text, long line) {
    hsbd_key_origin *r = &cfg->origins.key[config_key_index(k)];
    r->text = text_offset(&cfg->origins, text);
    r->kind = (uint8_t)kind;
    r->line = line;
}

void config_origin_from_file(hsbd_config *cfg, const key_spec *k, const char *path, long line) {
    record(cfg, k, ORIGIN_FILE, path, line);
}

void config_origin_from_set(hsbd_config *cfg, const key_spec *k, const char *origin) {
    record(cfg, k, ORIGIN_SET, origin, 0);
}

void config_origin_derived(hsbd_config *cfg, const char *section, const char *key,
                           const char *note) {
    record(cfg, config_find_key(section, key), ORIGIN_DERIVED, note, 0);
}

/* The next buffer of the ring: scratch of a configuration read through a const pointer, as
 * hsbd/config.h says (a configuration is never defined const). */
static char *ring_buffer(const hsbd_config *cfg) {
    hsbd_origins *o = (hsbd_origins *)&cfg->origins;
    char *buffer = o->ring[o->ring_next];
    o->ring_next = (uint16_t)((o->ring_next + 1) % HSBD_ORIGIN_RING);
    return buffer;
}

void config_origin_from_input(hsbd_config *cfg, const key_spec *k, const char *what) {
    record(cfg, k, ORIGIN_INPUT, what, 0);
}

int config_from_input(const hsbd_config *cfg, const char *section, const char *key) {
    return cfg->origins.key[config_key_index(config_find_key(section, key))].kind == ORIGIN_INPUT;
}

const char *config_origin_text(const hsbd_config *cfg, const key_spec *k) {
    const hsbd_key_origin *r = &cfg->origins.key[config_key_index(k)];
    const char *text = cfg->origins.texts + r->text;
    char *buffer;
    switch (r->kind) {
    case ORIGIN_FILE:
        buffer = ring_buffer(cfg);
        snprintf(buffer, HSBD_ORIGIN_MAX, "%s:%ld", text, r->line);
        return buffer;
    case ORIGIN_SET:
        buffer = ring_buffer(cfg);
        snprintf(buffer, HSBD_ORIGIN_MAX, "%s %s.%s", text, k->section, k->key);
        return buffer;
    case ORIGIN_DERIVED:
    case ORIGIN_INPUT:
        return text;
    default:
        return "default";
    }
}

static int at_default(const hsbd_config *cfg, const key_spec *k) {
    const int kind = cfg->origins.key[config_key_index(k)].kind;
    return kind == ORIGIN_DEFAULT || kind == ORIGIN_DERIVED;
}

int config_is_default(const hsbd_config *cfg, const char *section, const char *key) {
    return at_default(cfg, config_find_key(section, key));
}

const char *config_origin_of(const hsbd_config *cfg, const char *section, const char *key) {
    const key_spec *k = config_find_key(section, key);
    return at_default(cfg, k) && cfg->file[0] ? cfg->file : config_origin_text(cfg, k);
}

const char *hsbd_config_origin(const hsbd_config *cfg, const char *section, const char *key) {
    const key_spec *k = config_find_key(section, key);
    return k ? config_origin_text(cfg, k) : "";
}
