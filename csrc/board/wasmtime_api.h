/* The part of wasmtime's C API the WebAssembly board uses (the firmware_wasm*.c files), declared
 * as a table of function pointers filled from the wasmtime library the Python package `wasmtime`
 * ships (crslab/worker/wasm_runtime.py finds it; pyproject.toml pins its version, whose C ABI this
 * file follows: the opaque handles' layouts below are those of wasmtime 50's `wasmtime.h`), by
 * firmware_wasm_api.c. Nothing is linked against wasmtime at build time, so crslab._core builds
 * without its headers. Internal to the board; not read by cffi. */
#ifndef CRSLAB_WASMTIME_API_H
#define CRSLAB_WASMTIME_API_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct wasm_config_t wasm_config_t;
typedef struct wasm_engine_t wasm_engine_t;
typedef struct wasmtime_store wasmtime_store_t;
typedef struct wasmtime_context wasmtime_context_t;
typedef struct wasmtime_module wasmtime_module_t;
typedef struct wasmtime_linker wasmtime_linker_t;
typedef struct wasmtime_error wasmtime_error_t;
typedef struct wasm_trap_t wasm_trap_t;
typedef struct wasm_functype_t wasm_functype_t;
typedef struct wasm_externtype_t wasm_externtype_t;
typedef struct wasm_importtype_t wasm_importtype_t;
typedef struct wasm_frame_t wasm_frame_t;
typedef struct wasmtime_caller wasmtime_caller_t;

typedef struct {
    size_t size;
    char *data;
} wasm_byte_vec_t; /* also wasm_name_t and wasm_message_t */
typedef struct {
    size_t size;
    wasm_importtype_t **data;
} wasm_importtype_vec_t;
typedef struct {
    size_t size;
    wasm_frame_t **data;
} wasm_frame_vec_t;

/* Handles into a store: plain values, copied freely. */
typedef struct {
    uint64_t store_id;
    void *private_;
} wasmtime_func_t;
typedef struct {
    struct {
        uint64_t store_id;
        uint32_t private1;
    } anon;
    uint32_t private2; /* after the inner struct's padding: 24 bytes in all */
} wasmtime_memory_t;
typedef struct {
    uint64_t store_id;
    uint32_t private1, private2, private3;
} wasmtime_global_t;
typedef struct {
    uint64_t store_id;
    size_t private_;
} wasmtime_instance_t;

enum { WASMTIME_EXTERN_FUNC = 0, WASMTIME_EXTERN_GLOBAL = 1, WASMTIME_EXTERN_MEMORY = 3 };
typedef struct {
    uint8_t kind;
    union {
        wasmtime_func_t func;
        wasmtime_global_t global;
        wasmtime_memory_t memory;
        uint8_t size_[24];
    } of;
} wasmtime_extern_t;

enum { WASM_EXTERN_FUNC = 0 }; /* wasm_externtype_kind */
enum { WASMTIME_I32 = 0, WASMTIME_I64 = 1, WASMTIME_F32 = 2, WASMTIME_F64 = 3 };
typedef struct {
    uint8_t kind;
    union {
        int32_t i32;
        int64_t i64;
        float f32;
        double f64;
        uint8_t size_[24];
    } of;
} wasmtime_val_t;
typedef union {
    int32_t i32;
    int64_t i64;
    float f32;
    double f64;
    uint8_t v128[16];
    void *funcref;
} wasmtime_val_raw_t;

_Static_assert(sizeof(wasmtime_func_t) == 16 && sizeof(wasmtime_memory_t) == 24 && sizeof(wasmtime_global_t) == 24
                   && sizeof(wasmtime_instance_t) == 16 && sizeof(wasmtime_extern_t) == 32
                   && sizeof(wasmtime_val_t) == 32 && sizeof(wasmtime_val_raw_t) == 16,
               "the handles' layouts of wasmtime 50's wasmtime.h (x86-64, aarch64)");

/* What a store's epoch-deadline callback asks for (wasmtime_update_deadline_kind_t). */
enum { WASMTIME_UPDATE_DEADLINE_CONTINUE = 0, WASMTIME_UPDATE_DEADLINE_YIELD = 1 };
typedef wasmtime_error_t *(*wasmtime_epoch_deadline_callback_t)(wasmtime_context_t *context, void *data,
                                                                 uint64_t *epoch_deadline_delta,
                                                                 uint8_t *update_kind);

typedef wasm_trap_t *(*wasmtime_func_unchecked_callback_t)(void *env, wasmtime_caller_t *caller,
                                                            wasmtime_val_raw_t *args_and_results,
                                                            size_t num_args_and_results);

/* wasmtime_trap_code's codes the board tells apart */
enum {
    WASMTIME_TRAP_CODE_STACK_OVERFLOW = 0,
    WASMTIME_TRAP_CODE_MEMORY_OUT_OF_BOUNDS = 1,
    WASMTIME_TRAP_CODE_HEAP_MISALIGNED = 2,
    WASMTIME_TRAP_CODE_TABLE_OUT_OF_BOUNDS = 3,
    WASMTIME_TRAP_CODE_INDIRECT_CALL_TO_NULL = 4,
    WASMTIME_TRAP_CODE_BAD_SIGNATURE = 5,
    WASMTIME_TRAP_CODE_INTEGER_OVERFLOW = 6,
    WASMTIME_TRAP_CODE_INTEGER_DIVISION_BY_ZERO = 7,
    WASMTIME_TRAP_CODE_BAD_CONVERSION_TO_INTEGER = 8,
    WASMTIME_TRAP_CODE_UNREACHABLE_CODE_REACHED = 9,
    WASMTIME_TRAP_CODE_INTERRUPT = 10,
    WASMTIME_TRAP_CODE_OUT_OF_FUEL = 11
};

typedef struct {
    wasm_config_t *(*config_new)(void);
    void (*config_consume_fuel_set)(wasm_config_t *, bool);
    void (*config_epoch_interruption_set)(wasm_config_t *, bool);
    void (*config_parallel_compilation_set)(wasm_config_t *, bool);
    void (*config_max_wasm_stack_set)(wasm_config_t *, size_t);
    void (*config_memory_reservation_set)(wasm_config_t *, uint64_t);
    void (*config_memory_guard_size_set)(wasm_config_t *, uint64_t);
    void (*config_memory_reservation_for_growth_set)(wasm_config_t *, uint64_t);
    void (*config_memory_may_move_set)(wasm_config_t *, bool);
    void (*config_wasm_threads_set)(wasm_config_t *, bool);
    wasm_engine_t *(*engine_new_with_config)(wasm_config_t *);
    void (*engine_delete)(wasm_engine_t *);
    void (*engine_increment_epoch)(wasm_engine_t *);
    wasmtime_error_t *(*module_new)(wasm_engine_t *, const uint8_t *, size_t, wasmtime_module_t **);
    void (*module_delete)(wasmtime_module_t *);
    wasmtime_error_t *(*module_serialize)(wasmtime_module_t *, wasm_byte_vec_t *);
    wasmtime_error_t *(*module_deserialize)(wasm_engine_t *, const uint8_t *, size_t, wasmtime_module_t **);
    void (*module_imports)(const wasmtime_module_t *, wasm_importtype_vec_t *);
    void (*importtype_vec_delete)(wasm_importtype_vec_t *);
    const wasm_byte_vec_t *(*importtype_module)(const wasm_importtype_t *);
    const wasm_byte_vec_t *(*importtype_name)(const wasm_importtype_t *);
    const wasm_externtype_t *(*importtype_type)(const wasm_importtype_t *);
    uint8_t (*externtype_kind)(const wasm_externtype_t *);
    const wasm_functype_t *(*externtype_as_functype_const)(const wasm_externtype_t *);
    wasmtime_store_t *(*store_new)(wasm_engine_t *, void *, void (*)(void *));
    void (*store_delete)(wasmtime_store_t *);
    wasmtime_context_t *(*store_context)(wasmtime_store_t *);
    void (*store_epoch_deadline_callback)(wasmtime_store_t *, wasmtime_epoch_deadline_callback_t, void *,
                                          void (*)(void *));
    void (*store_limiter)(wasmtime_store_t *, int64_t memory_size, int64_t table_elements,
                          int64_t instances, int64_t tables, int64_t memories);
    void *(*context_get_data)(const wasmtime_context_t *);
    wasmtime_error_t *(*context_set_fuel)(wasmtime_context_t *, uint64_t);
    wasmtime_error_t *(*context_get_fuel)(const wasmtime_context_t *, uint64_t *);
    wasmtime_linker_t *(*linker_new)(wasm_engine_t *);
    void (*linker_delete)(wasmtime_linker_t *);
    wasmtime_error_t *(*linker_define_func_unchecked)(wasmtime_linker_t *, const char *, size_t,
                                                      const char *, size_t, const wasm_functype_t *,
                                                      wasmtime_func_unchecked_callback_t, void *,
                                                      void (*)(void *));
    wasmtime_error_t *(*linker_instantiate)(const wasmtime_linker_t *, wasmtime_context_t *,
                                            const wasmtime_module_t *, wasmtime_instance_t *,
                                            wasm_trap_t **);
    bool (*instance_export_get)(wasmtime_context_t *, const wasmtime_instance_t *, const char *, size_t,
                                wasmtime_extern_t *);
    void (*global_get)(wasmtime_context_t *, const wasmtime_global_t *, wasmtime_val_t *);
    wasmtime_error_t *(*func_call_unchecked)(wasmtime_context_t *, const wasmtime_func_t *,
                                             wasmtime_val_raw_t *, size_t, wasm_trap_t **);
    wasmtime_context_t *(*caller_context)(wasmtime_caller_t *);
    uint8_t *(*memory_data)(const wasmtime_context_t *, const wasmtime_memory_t *);
    size_t (*memory_data_size)(const wasmtime_context_t *, const wasmtime_memory_t *);
    wasm_trap_t *(*trap_new)(const char *, size_t);
    bool (*trap_code)(const wasm_trap_t *, uint8_t *);
    void (*trap_message)(const wasm_trap_t *, wasm_byte_vec_t *);
    void (*trap_delete)(wasm_trap_t *);
    void (*trap_trace)(const wasm_trap_t *, wasm_frame_vec_t *);
    void (*frame_vec_delete)(wasm_frame_vec_t *);
    const wasm_byte_vec_t *(*frame_func_name)(const wasm_frame_t *);
    size_t (*frame_module_offset)(const wasm_frame_t *);
    wasmtime_error_t *(*error_new)(const char *);
    void (*error_message)(const wasmtime_error_t *, wasm_byte_vec_t *);
    void (*error_delete)(wasmtime_error_t *);
    bool (*error_exit_status)(const wasmtime_error_t *, int *);
    void (*byte_vec_delete)(wasm_byte_vec_t *);
} crs_wasmtime_api;

/* wasmtime's functions, once crs_wasmtime_load has filled them (the same for every board of the
 * process). */
extern crs_wasmtime_api crs_wasmtime;

/* Fill crs_wasmtime from the wasmtime library at `path` (opened once per process); 0, or -1 with a
 * message in error[cap]. */
int crs_wasmtime_load(const char *path, char *error, size_t cap);

#endif
