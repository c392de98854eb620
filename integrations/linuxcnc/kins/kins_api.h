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

/* The machine's home identity (the module's #904, the parameter home=): a
   whole number 0..65535, absent 0; 0, or -1 with *why. A table file is
   loaded only when it was measured under it; trueaxis_kins_file_home() is the
   last file's (cradle_kinematics.hpp convention 8). */
int trueaxis_kins_set_home(const char* home, const char** why);
unsigned trueaxis_kins_file_home(void);
unsigned trueaxis_kins_home(void);

/* The loaded table: its pose count (0: none, the ideal cradle) and A range. */
size_t trueaxis_kins_poses(void);
double trueaxis_kins_a_min_deg(void);
double trueaxis_kins_a_max_deg(void);

/* Loads the spindle model file at `path` (record_file.hpp of the M4 record);
   0, or -1 with *why (the model then stays as it was: none at start). */
int trueaxis_kins_load_spindle(const char* path, const char** why);

/* 1 when a spindle model is loaded. */
int trueaxis_kins_spindle_loaded(void);

/* The tool tip's error (mm, machine axes) at spindle angle phi_deg and tool
   length tool_mm below the gauge line (cradle_kinematics.hpp convention 5,
   9843's answer); 0, or -1 without a model or for an input 9843 refuses. */
int trueaxis_kins_tip_error(double phi_deg, double tool_mm, double error_mm[3]);

/* The machine's linear units ([TRAJ] LINEAR_UNITS, the module's
   `linear_units` parameter): "mm" or "metric" (the start), "inch", "in"
   or "imperial"; the tables are in
   mm, so on an inch machine the world, the joints and the tool offset are
   converted (25.4 mm an inch) on the way in and out. 0, or -1 with *why for
   anything else (the units stay as they were). */
int trueaxis_kins_set_linear_units(const char* units, const char** why);

/* The ideal cradle's nominal pivot (cradle_kinematics.hpp convention 2), in
   the machine's linear units (set them first): rot_point "X,Y,Z", the C
   axis' point at A = 0 (xyzac-trt-kins' x/y/z-rot-point), and a_offset
   "DY,DZ", the A axis' from it (its y-offset, z-offset); NULL or "" for 0.
   0, or -1 with *why (nothing changed) for anything but that many finite
   numbers. A loaded table's measured axes replace the pivot. */
int trueaxis_kins_set_pivot(const char* rot_point, const char* a_offset, const char** why);

/* LinuxCNC's kinematics, whole (cradle_kinematics.hpp conventions 1-6):
   world (table) coordinates to the joints' X, Y, Z at commanded A, C and
   back, in the machine's linear units; `type` 0 the identity or 1 the
   cradle; `tool` the active tool offset (motion.tooloffset.z: the tip that
   far below the gauge line, along the machine's -Z); when `tip` is not 0,
   the tool tip's error at phi_deg and that length taken off the joints
   (added back going forward). 0 on success, -1 for a non-finite input, a
   tip asked for without a spindle model, or a tool offset the model refuses
   (the output untouched). */
int trueaxis_kins_to_joints(int type, const double world[3], double a_deg, double c_deg, double tool, int tip,
                            double phi_deg, double joint[3]);
int trueaxis_kins_to_world(int type, const double joint[3], double a_deg, double c_deg, double tool, int tip,
                           double phi_deg, double world[3]);

/* The servo thread's tip correction (cradle_kinematics.hpp convention 7):
   its target, mode 0 none (zero), 1 at phi_deg, 2 the mean over a
   revolution (a rotating tool), at the tool offset `tool` (machine units),
   in mm; 0, or -1 without a model or at a length it refuses (target
   untouched). Then one period's step of `applied` (mm) towards it, at most
   ramp_mm long (not above 0: the default 0.5 um): 1 when it has arrived, 0
   while it ramps. */
int trueaxis_kins_tip_target(int mode, double phi_deg, double tool, double target_mm[3]);
int trueaxis_kins_tip_ramp(const double target_mm[3], double ramp_mm, double applied_mm[3]);

/* The kinematics with the tip's error given (mm: the ramped one), in place of
   `tip` and phi_deg: -1 only for a non-finite input. */
int trueaxis_kins_to_joints_with(int type, const double world[3], double a_deg, double c_deg, double tool,
                                 const double tip_error_mm[3], double joint[3]);
int trueaxis_kins_to_world_with(int type, const double joint[3], double a_deg, double c_deg, double tool,
                                const double tip_error_mm[3], double world[3]);

#ifdef __cplusplus
}
#endif

#endif
