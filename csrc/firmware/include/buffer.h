/* crslab host stand-in for buffer.h of the Gen B "me446 starter" framework: the transmit ring
 * types of the three serial ports and their small inline helpers (crslab's own ring; the board's
 * serial line itself is csrc/board/serial_line.c), and, as on the board, the device header. */
#ifndef CRSLAB_BUFFER_H
#define CRSLAB_BUFFER_H

#include "DSP2833x_Device.h"

#define BUF_SIZESCIA (136) /* bytes: the transmit ring of SerialA (Tera Term) */
#define BUF_SIZESCIB (136)
#define BUF_SIZESCIC (2000)

/* One ring per port: head is where the next byte goes, tail the oldest byte, size the count. */
#define CRSLAB_RING(port, capacity)                                                           \
    typedef volatile struct buffer##port##_s {                                                 \
        volatile char buf[capacity];                                                           \
        volatile Uint16 head, tail, size;                                                      \
    } buffer##port##_t;                                                                        \
    static inline void init_buffer##port(buffer##port##_t *b) { b->size = b->head = b->tail = 0; } \
    static inline uint16_t buf_write##port##_1(buffer##port##_t *b, char data)                 \
    {                                                                                          \
        if (b->size >= (capacity)) return 2; /* full */                                        \
        b->buf[b->head] = data;                                                                \
        b->head = (Uint16)((b->head + 1u) % (capacity));                                       \
        b->size++;                                                                             \
        return 0;                                                                              \
    }                                                                                          \
    static inline uint16_t buf_read##port##_1(buffer##port##_t *b, Uint16 offset, char *data)  \
    {                                                                                          \
        if (b->size == 0 || b->size < offset) return 3; /* nothing there */                    \
        *data = b->buf[(b->tail + offset) % (capacity)];                                       \
        return 0;                                                                              \
    }                                                                                          \
    static inline uint16_t buf_remove##port(buffer##port##_t *b, Uint16 len)                   \
    {                                                                                          \
        Uint16 n = len > b->size ? b->size : len;                                              \
        b->tail = (Uint16)((b->tail + n) % (capacity));                                        \
        b->size = (Uint16)(b->size - n);                                                       \
        return n;                                                                              \
    }

CRSLAB_RING(SCIA, BUF_SIZESCIA)
CRSLAB_RING(SCIB, BUF_SIZESCIB)
CRSLAB_RING(SCIC, BUF_SIZESCIC)
#undef CRSLAB_RING

#define buf_clearSCIA(b) init_bufferSCIA(b)
#define buf_clearSCIB(b) init_bufferSCIB(b)
#define buf_clearSCIC(b) init_bufferSCIC(b)

#endif
