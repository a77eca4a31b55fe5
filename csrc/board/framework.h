/* Internal: the pieces of the real framework's 1 ms tick (docs/framework.md sections 3 and 4). */
#ifndef CRSLAB_FRAMEWORK_H
#define CRSLAB_FRAMEWORK_H

#include "board.h"

/* Encoder angles (rad) the framework hands to lab(), from the plant's true motor angles. */
void crs_read_encoders(crs_board *board, const double motor_rad[3], double enc_rad[3]);
/* The hold controller's every-tick update (from tick 0 on): velocity filter and output
 * h->out for this tick's angles, toward the references as they stand. */
void crs_hold_update(crs_hold *h, const double enc_rad[3]);
/* Inside the envelope (from the startup gate on, after lab()): the references follow the arm. */
void crs_hold_follow(crs_hold *h, const double enc_rad[3]);
/* Outside: a reference more than CRS_HOLD_REANCHOR_RAD from its angle moves to the angle
 * (effective next tick), so an arm pushed far out is held about where it is. */
void crs_hold_reanchor(crs_hold *h, const double enc_rad[3]);

#endif
