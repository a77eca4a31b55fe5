/* crslab host stand-in for TI's tistdtypes.h (Gen A "CRSRobot" framework): the TI integer
 * and boolean type names, sized as on the C28x where it matters to a lab file. */
#ifndef CRSLAB_TISTDTYPES_H
#define CRSLAB_TISTDTYPES_H

#include <stdint.h>

typedef int16_t Int16;
typedef uint16_t Uint16;
typedef int32_t Int32;
typedef uint32_t Uint32;
typedef int64_t Int64;
typedef uint64_t Uint64;
typedef int8_t Int8;
typedef uint8_t Uint8;
typedef float Float32;
typedef unsigned short Bool; /* never "typedef int bool": it would break <stdbool.h> */
typedef char *String;
typedef void *Ptr;
typedef int Int;
typedef unsigned int Uns;
typedef char Char;

#ifndef TRUE
#define TRUE ((Bool)1)
#define FALSE ((Bool)0)
#endif

#endif
