/* The cradle kinematics (cradle_kinematics.hpp) behind a C interface, for
   trueaxis_kins.c: LinuxCNC's kinematics headers are C (posemath's C++
   overloads forbid them inside extern "C"), so the real-time glue is C and
   the computation stays the project's C++. One instance per process, as
   LinuxCNC loads one kinematics module. */
#ifndef TRUEAXIS_KINS_API_H
#define TRUEAXIS_KINS_API_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Loads the table file at `path` (record_file.hpp of the rigidity record);
   0 on success, -1 with *why one line when it cannot be read or does not
   check (the kinematics then stay the ideal cradle). */
int trueaxis_kins_load(const char* path, const char** why);

/* The loaded table: its pose count (0: none, the ideal cradle) and A range. */
size_t trueaxis_kins_poses(void);
double trueaxis_kins_a_min_deg(void);
double trueaxis_kins_a_max_deg(void);

/* Table (world) coordinates to the joints' X, Y, Z at commanded A, C, and
   back (cradle_kinematics.hpp conventions 1-3); 0 on success, -1 for a
   non-finite input (the output untouched). */
int trueaxis_kins_inverse(const double world_mm[3], double a_deg, double c_deg, double joint_mm[3]);
int trueaxis_kins_forward(const double joint_mm[3], double a_deg, double c_deg, double world_mm[3]);

#ifdef __cplusplus
}
#endif

#endif
