/* The emulated C28x data memory: what the board's MATLAB code reads and writes at a 16-bit-word
 * address (docs/host-tools.md, "SerialC: a MATLAB message"). Every word belongs to one of the
 * lab's globals (laid out by crslab/lab/c28x_memory.py, filled in by the worker) or to
 * nothing; a word is made
 * from the variable's current value in the worker as the C28x holds it: an int is 16 bits, a long
 * and a float two words, low word first. Internal to the board; not read by cffi. */
#ifndef CRSLAB_C28X_MEMORY_H
#define CRSLAB_C28X_MEMORY_H

#include <stdint.h>

#include "board.h"

/* The 16-bit word at `address` (0 where no variable lies). */
uint16_t crs_mem_read_word(const crs_c28x_memory *mem, uint32_t address);
/* Store a 16-bit word at `address` into the variable there (ignored where none lies, or for a
 * const, a pointer or a variable crslab cannot reach). */
void crs_mem_write_word(const crs_c28x_memory *mem, uint32_t address, uint16_t word);
/* A 32-bit access, as the C28x makes it: at the even address at or below `address` (the CPU
 * ignores the lowest bit), low word first. */
uint32_t crs_mem_read32(const crs_c28x_memory *mem, uint32_t address);
void crs_mem_write32(const crs_c28x_memory *mem, uint32_t address, uint32_t value);

#endif
