/* crslab host stand-in for DSP28x_Project.h: the device header (types, GPIO, no-op macros). */
#ifndef CRSLAB_DSP28X_PROJECT_H
#define CRSLAB_DSP28X_PROJECT_H

#include "DSP2833x_Device.h"

#endif
