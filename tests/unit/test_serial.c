/* The checkpoint serialisation: values come back bit for bit, every read of data that
 * end early or have another shape fails (and the reader stays failed), and the CRC-64 is
 * the standard one (ECMA-182 reflected, "123456789" -> 0x995dc9bbdf1939fa). */
#include <math.h>
#include <string.h>

#include "../test_util.h"
#include "core/serial.h"

int main(void) {
    CHECK(hsbd_crc64(0, "123456789", 9) == 0x995dc9bbdf1939faull, "crc64 check value %llx",
          (unsigned long long)hsbd_crc64(0, "123456789", 9));
    const uint64_t crc = hsbd_crc64(hsbd_crc64(0, "1234", 4), "56789", 5);
    CHECK(crc == 0x995dc9bbdf1939faull, "crc64 in two parts");

    hsbd_writer w;
    hsbd_writer_init(&w);
    const double v[4] = {1.0 / 3.0, -0.0, NAN, 1e-310};
    const int ints[3] = {-7, 0, 2147483647};
    hsbd_put_tag(&w, "section");
    hsbd_put_u64(&w, 0xfedcba9876543210ull);
    hsbd_put_i64(&w, -5);
    hsbd_put_f64s(&w, v, 4);
    hsbd_put_ints(&w, ints, 3);
    hsbd_put_string(&w, "name");
    CHECK(!w.oom, "writer");

    hsbd_reader r;
    hsbd_reader_init(&r, w.data, w.len);
    uint64_t u;
    int64_t i;
    double back[4];
    int iback[3];
    char s[8];
    CHECK(hsbd_get_tag(&r, "section") == 0 && hsbd_get_u64(&r, &u) == 0 &&
              u == 0xfedcba9876543210ull && hsbd_get_i64(&r, &i) == 0 && i == -5,
          "scalars");
    CHECK(hsbd_get_f64s(&r, back, 4) == 0 && memcmp(back, v, sizeof v) == 0, "doubles bit for bit");
    CHECK(hsbd_get_ints(&r, iback, 3) == 0 && memcmp(iback, ints, sizeof ints) == 0, "ints");
    CHECK(hsbd_get_string(&r, s, sizeof s) == 0 && !strcmp(s, "name"), "string");
    CHECK(r.pos == w.len && !r.bad, "everything read");

    /* every truncation fails somewhere, never reads beyond the end */
    for (size_t cut = 0; cut < w.len; ++cut) {
        hsbd_reader_init(&r, w.data, cut);
        hsbd_get_tag(&r, "section");
        hsbd_get_u64(&r, &u);
        hsbd_get_i64(&r, &i);
        hsbd_get_f64s(&r, back, 4);
        hsbd_get_ints(&r, iback, 3);
        hsbd_get_string(&r, s, sizeof s);
        CHECK(r.bad && r.pos <= cut, "cut at %zu: bad %d pos %zu", cut, r.bad, r.pos);
    }
    /* another shape, another tag, a string too long for its buffer */
    hsbd_reader_init(&r, w.data, w.len);
    CHECK(hsbd_get_tag(&r, "other") != 0 && r.bad && strstr(r.why, "other"), "tag: %s", r.why);
    hsbd_reader_init(&r, w.data, w.len);
    hsbd_get_tag(&r, "section"), hsbd_get_u64(&r, &u), hsbd_get_i64(&r, &i);
    CHECK(hsbd_get_f64s(&r, back, 3) != 0 && strstr(r.why, "4 values stored, 3 expected"),
          "count: %s", r.why);
    CHECK(hsbd_get_u64(&r, &u) != 0, "a failed reader stays failed");
    hsbd_reader_init(&r, w.data, w.len);
    hsbd_get_tag(&r, "section"), hsbd_get_u64(&r, &u), hsbd_get_i64(&r, &i);
    hsbd_get_f64s(&r, back, 4), hsbd_get_ints(&r, iback, 3);
    char small[4];
    CHECK(hsbd_get_string(&r, small, sizeof small) != 0, "string longer than its buffer");
    /* a count of 2^63 never allocates or reads: it is compared, then refused */
    hsbd_writer big;
    hsbd_writer_init(&big);
    hsbd_put_u64(&big, (uint64_t)1 << 63);
    hsbd_reader_init(&r, big.data, big.len);
    CHECK(hsbd_get_f64s(&r, back, 4) != 0, "huge count");
    hsbd_writer_free(&big);
    hsbd_writer_free(&w);
    return test_finish("test_serial");
}
