/* crslab host stand-in for user_includes.h of the Gen A framework: the prototypes the
 * framework expects the lab file to define. */
#ifndef CRSLAB_USER_INCLUDES_H
#define CRSLAB_USER_INCLUDES_H

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error);
void printing(void);

#endif
