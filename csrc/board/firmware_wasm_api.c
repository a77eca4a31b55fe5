/* wasmtime's C library, loaded at run time (wasmtime_api.h): the library the Python package
 * `wasmtime` ships is opened by its path once per process and every function the board uses is
 * looked up by name into crs_wasmtime, so crslab._core is built without wasmtime's headers and a
 * library that lacks one is refused with its name. */
#include "wasmtime_api.h"

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

crs_wasmtime_api crs_wasmtime;
static int loaded;

#define LOAD_SYMBOL(field, symbol)                                                  \
    do {                                                                            \
        void *f = dlsym(lib, #symbol);                                              \
        if (f == NULL) {                                                            \
            snprintf(error, cap, "%s lacks %s: not the wasmtime crslab needs", path, #symbol); \
            return -1;                                                              \
        }                                                                           \
        memcpy(&crs_wasmtime.field, &f, sizeof f);                                  \
    } while (0)

int crs_wasmtime_load(const char *path, char *error, size_t cap)
{
    if (loaded) return 0;
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        snprintf(error, cap, "cannot load wasmtime (%s)", dlerror());
        return -1;
    }
    LOAD_SYMBOL(config_new, wasm_config_new);
    LOAD_SYMBOL(config_consume_fuel_set, wasmtime_config_consume_fuel_set);
    LOAD_SYMBOL(config_epoch_interruption_set, wasmtime_config_epoch_interruption_set);
    LOAD_SYMBOL(config_parallel_compilation_set, wasmtime_config_parallel_compilation_set);
    LOAD_SYMBOL(config_max_wasm_stack_set, wasmtime_config_max_wasm_stack_set);
    LOAD_SYMBOL(config_memory_reservation_set, wasmtime_config_memory_reservation_set);
    LOAD_SYMBOL(config_memory_guard_size_set, wasmtime_config_memory_guard_size_set);
    LOAD_SYMBOL(config_memory_reservation_for_growth_set, wasmtime_config_memory_reservation_for_growth_set);
    LOAD_SYMBOL(config_memory_may_move_set, wasmtime_config_memory_may_move_set);
    LOAD_SYMBOL(config_wasm_threads_set, wasmtime_config_wasm_threads_set);
    LOAD_SYMBOL(engine_new_with_config, wasm_engine_new_with_config);
    LOAD_SYMBOL(engine_delete, wasm_engine_delete);
    LOAD_SYMBOL(engine_increment_epoch, wasmtime_engine_increment_epoch);
    LOAD_SYMBOL(module_new, wasmtime_module_new);
    LOAD_SYMBOL(module_delete, wasmtime_module_delete);
    LOAD_SYMBOL(module_serialize, wasmtime_module_serialize);
    LOAD_SYMBOL(module_deserialize, wasmtime_module_deserialize);
    LOAD_SYMBOL(module_imports, wasmtime_module_imports);
    LOAD_SYMBOL(importtype_vec_delete, wasm_importtype_vec_delete);
    LOAD_SYMBOL(importtype_module, wasm_importtype_module);
    LOAD_SYMBOL(importtype_name, wasm_importtype_name);
    LOAD_SYMBOL(importtype_type, wasm_importtype_type);
    LOAD_SYMBOL(externtype_kind, wasm_externtype_kind);
    LOAD_SYMBOL(externtype_as_functype_const, wasm_externtype_as_functype_const);
    LOAD_SYMBOL(store_new, wasmtime_store_new);
    LOAD_SYMBOL(store_delete, wasmtime_store_delete);
    LOAD_SYMBOL(store_context, wasmtime_store_context);
    LOAD_SYMBOL(store_epoch_deadline_callback, wasmtime_store_epoch_deadline_callback);
    LOAD_SYMBOL(store_limiter, wasmtime_store_limiter);
    LOAD_SYMBOL(context_get_data, wasmtime_context_get_data);
    LOAD_SYMBOL(context_set_fuel, wasmtime_context_set_fuel);
    LOAD_SYMBOL(context_get_fuel, wasmtime_context_get_fuel);
    LOAD_SYMBOL(linker_new, wasmtime_linker_new);
    LOAD_SYMBOL(linker_delete, wasmtime_linker_delete);
    LOAD_SYMBOL(linker_define_func_unchecked, wasmtime_linker_define_func_unchecked);
    LOAD_SYMBOL(linker_instantiate, wasmtime_linker_instantiate);
    LOAD_SYMBOL(instance_export_get, wasmtime_instance_export_get);
    LOAD_SYMBOL(global_get, wasmtime_global_get);
    LOAD_SYMBOL(func_call_unchecked, wasmtime_func_call_unchecked);
    LOAD_SYMBOL(caller_context, wasmtime_caller_context);
    LOAD_SYMBOL(memory_data, wasmtime_memory_data);
    LOAD_SYMBOL(memory_data_size, wasmtime_memory_data_size);
    LOAD_SYMBOL(trap_new, wasmtime_trap_new);
    LOAD_SYMBOL(trap_code, wasmtime_trap_code);
    LOAD_SYMBOL(trap_message, wasm_trap_message);
    LOAD_SYMBOL(trap_delete, wasm_trap_delete);
    LOAD_SYMBOL(trap_trace, wasm_trap_trace);
    LOAD_SYMBOL(frame_vec_delete, wasm_frame_vec_delete);
    LOAD_SYMBOL(frame_func_name, wasmtime_frame_func_name);
    LOAD_SYMBOL(frame_module_offset, wasm_frame_module_offset);
    LOAD_SYMBOL(error_new, wasmtime_error_new);
    LOAD_SYMBOL(error_message, wasmtime_error_message);
    LOAD_SYMBOL(error_delete, wasmtime_error_delete);
    LOAD_SYMBOL(error_exit_status, wasmtime_error_exit_status);
    LOAD_SYMBOL(byte_vec_delete, wasm_byte_vec_delete);
    loaded = 1;
    return 0;
}
