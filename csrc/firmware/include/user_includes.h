/* crslab host stand-in for user_includes.h of the Gen A framework. The framework declares lab()
 * in its own C file, not here, and calls it through that declaration: so a lab file may define
 * lab() with fewer parameters (the six without `error`, or none) or K&R style, and the board
 * runs it (crslab/lab/entry_points.py). printing(), which the framework's software interrupt
 * runs, is declared for labs that call it before defining it. */
#ifndef CRSLAB_USER_INCLUDES_H
#define CRSLAB_USER_INCLUDES_H

void printing(void);

#endif
