/* The emulated C28x data memory over the lab's globals. */
#include "c28x_memory.h"

#include <string.h>

enum { MAX_WORDS = 4 };

/* The variable holding `address`, or NULL. */
static const crs_mem_var *find(const crs_c28x_memory *mem, uint32_t address)
{
    uint32_t lo = 0, hi = mem->count;
    while (lo < hi) { /* the first variable starting beyond address */
        const uint32_t mid = lo + (hi - lo) / 2;
        if (mem->vars[mid].address <= address) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    if (lo == 0) return NULL;
    const crs_mem_var *v = &mem->vars[lo - 1];
    const uint64_t end = (uint64_t)v->address + (uint64_t)v->count * v->words;
    return address < end ? v : NULL;
}

static int reachable(const crs_mem_var *v)
{
    return v->host != NULL && v->kind != CRS_MEM_OPAQUE && v->words >= 1 && v->words <= MAX_WORDS
           && v->host_bytes >= 1 && v->host_bytes <= 16;
}

/* An integer element as a 64-bit pattern (sign- or zero-extended from its host size). */
static uint64_t host_integer(const unsigned char *p, uint32_t bytes, int is_signed)
{
    uint64_t v = 0;
    memcpy(&v, p, bytes > 8 ? 8 : bytes); /* little-endian host */
    if (bytes < 8) {
        const uint64_t sign = (uint64_t)1 << (8 * bytes - 1);
        v &= (sign << 1) - 1;
        if (is_signed && (v & sign)) v |= ~((sign << 1) - 1);
    }
    return v;
}

/* A host real of `bytes` bytes (float, double or long double) at p, widened exactly. */
static long double host_real(const unsigned char *p, size_t bytes)
{
    if (bytes == sizeof(float)) {
        float f;
        memcpy(&f, p, sizeof f);
        return f;
    }
    if (bytes == sizeof(double)) {
        double d;
        memcpy(&d, p, sizeof d);
        return d;
    }
    long double ld;
    memcpy(&ld, p, sizeof ld);
    return ld;
}

static void element_words(const crs_mem_var *v, uint32_t index, uint16_t out[MAX_WORDS])
{
    const unsigned char *p = (const unsigned char *)v->host + (size_t)index * v->host_bytes;
    uint64_t bits = 0;
    if (v->kind == CRS_MEM_FLOAT) {
        long double value = host_real(p, v->host_bytes); /* exact: every host real widens to it */
        if (v->words == 2) { /* a C28x float (or double, 32 bits under the COFF ABI) */
            float f = (float)value;
            uint32_t b;
            memcpy(&b, &f, sizeof b);
            bits = b;
        } else { /* a C28x long double: IEEE double */
            double d = (double)value;
            memcpy(&bits, &d, sizeof bits);
        }
    } else if (v->kind == CRS_MEM_BOOL) {
        bits = host_integer(p, v->host_bytes, 0) != 0;
    } else {
        bits = host_integer(p, v->host_bytes, v->kind == CRS_MEM_SIGNED);
    }
    for (uint32_t w = 0; w < MAX_WORDS; ++w) out[w] = w < v->words ? (uint16_t)(bits >> (16 * w)) : 0;
}

static void store_element(const crs_mem_var *v, uint32_t index, const uint16_t in[MAX_WORDS])
{
    unsigned char *p = (unsigned char *)v->host + (size_t)index * v->host_bytes;
    uint64_t bits = 0;
    for (uint32_t w = 0; w < v->words; ++w) bits |= (uint64_t)in[w] << (16 * w);
    if (v->kind == CRS_MEM_FLOAT) {
        if (v->words == 2) {
            const uint32_t b = (uint32_t)bits;
            float f;
            memcpy(&f, &b, sizeof f);
            if (v->host_bytes == sizeof(float)) {
                memcpy(p, &f, sizeof f);
            } else if (v->host_bytes == sizeof(double)) {
                const double d = f;
                memcpy(p, &d, sizeof d);
            } else {
                const long double d = f;
                memcpy(p, &d, sizeof d);
            }
        } else {
            double d;
            memcpy(&d, &bits, sizeof d);
            if (v->host_bytes == sizeof(double)) {
                memcpy(p, &d, sizeof d);
            } else if (v->host_bytes == sizeof(float)) {
                const float f = (float)d;
                memcpy(p, &f, sizeof f);
            } else {
                const long double ld = d;
                memcpy(p, &ld, sizeof ld);
            }
        }
        return;
    }
    if (v->kind == CRS_MEM_BOOL) {
        const unsigned char b = bits != 0;
        memset(p, 0, v->host_bytes);
        memcpy(p, &b, 1);
        return;
    }
    /* an integer: the C28x value (16 * words bits), sign-extended for a signed type, then as
     * many of its low bytes as the host type holds */
    const uint32_t nbits = 16 * v->words;
    if (nbits < 64 && v->kind == CRS_MEM_SIGNED && (bits >> (nbits - 1)) & 1) bits |= ~0ULL << nbits;
    memcpy(p, &bits, v->host_bytes > 8 ? 8 : v->host_bytes);
}

uint16_t crs_mem_read_word(const crs_c28x_memory *mem, uint32_t address)
{
    const crs_mem_var *v = find(mem, address);
    if (v == NULL || !reachable(v)) return 0;
    const uint32_t offset = address - v->address;
    uint16_t words[MAX_WORDS];
    element_words(v, offset / v->words, words);
    return words[offset % v->words];
}

void crs_mem_write_word(const crs_c28x_memory *mem, uint32_t address, uint16_t word)
{
    const crs_mem_var *v = find(mem, address);
    if (v == NULL || !reachable(v) || !v->writable) return;
    const uint32_t offset = address - v->address;
    uint16_t words[MAX_WORDS];
    element_words(v, offset / v->words, words);
    words[offset % v->words] = word;
    store_element(v, offset / v->words, words);
}

uint32_t crs_mem_read32(const crs_c28x_memory *mem, uint32_t address)
{
    const uint32_t even = address & ~1u;
    return (uint32_t)crs_mem_read_word(mem, even) | (uint32_t)crs_mem_read_word(mem, even + 1) << 16;
}

void crs_mem_write32(const crs_c28x_memory *mem, uint32_t address, uint32_t value)
{
    const uint32_t even = address & ~1u;
    crs_mem_write_word(mem, even, (uint16_t)value);
    crs_mem_write_word(mem, even + 1, (uint16_t)(value >> 16));
}
