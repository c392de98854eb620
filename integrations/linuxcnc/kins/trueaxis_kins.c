/* trueaxis_kins: LinuxCNC kinematics for an XYZAC cradle machine on its
   calibrated axes (cradle_kinematics.hpp through kins_api.h), a real-time
   module for LinuxCNC 2.9 (uspace). In the ini:
       [KINS]
       KINEMATICS = trueaxis_kins table=/path/to/m3.table
       JOINTS = 5
   `table` is the file `trueaxis-calibrate rigidity --store --linuxcnc-kins`
   (or `trueaxis-calibrate linuxcnc-kins`) writes from the controller's stored
   M3 table. Without `table` the machine is the ideal cradle; a `table` that
   cannot be read or does not check stops LinuxCNC's start with one line
   naming the file and why: a machine never runs on ideal axes in place of a
   calibration it was given.
   Switchable (motion.switchkins-type): 0 identity (machine coordinates, for
   probing programs; the start), 1 the cradle's table coordinates. */
#include "kins_api.h"

#include "hal.h"
#include "kinematics.h"
#include "rtapi.h"
#include "rtapi_app.h"
#include "rtapi_errno.h"

MODULE_AUTHOR("trueaxis");
MODULE_DESCRIPTION("XYZAC cradle kinematics on the axes of a trueaxis M3 table");
MODULE_LICENSE("GPL");

static char* table = 0;
RTAPI_MP_STRING(table, "the M3 table file (trueaxis-calibrate rigidity --store --linuxcnc-kins); absent: the ideal cradle");

static int comp_id = -1;
static int kins_type = 0; /* switchkins type: 0 identity, 1 the cradle */

int rtapi_app_main(void) {
  comp_id = hal_init("trueaxis_kins");
  if (comp_id < 0) return comp_id;
  if (table != 0 && table[0] != '\0') {
    const char* why = "";
    if (trueaxis_kins_load(table, &why) != 0) {
      rtapi_print_msg(RTAPI_MSG_ERR,
                      "trueaxis_kins: table %s: %s; the machine does not start on ideal axes in its place "
                      "(write the file again: trueaxis-calibrate rigidity --store --linuxcnc-kins FILE)\n",
                      table, why);
      hal_exit(comp_id);
      return -EINVAL;
    }
    rtapi_print_msg(RTAPI_MSG_INFO, "trueaxis_kins: table %s: %d poses, A %g .. %g deg\n", table,
                    (int)trueaxis_kins_poses(), trueaxis_kins_a_min_deg(), trueaxis_kins_a_max_deg());
  } else {
    rtapi_print_msg(RTAPI_MSG_INFO, "trueaxis_kins: no table: the ideal cradle Rx(A) Rz(C)\n");
  }
  hal_ready(comp_id);
  return 0;
}

void rtapi_app_exit(void) { hal_exit(comp_id); }

KINEMATICS_TYPE kinematicsType(void) { return KINEMATICS_BOTH; }

int kinematicsSwitchable(void) { return 1; }

int kinematicsSwitch(int switchkins_type) {
  if (switchkins_type != 0 && switchkins_type != 1) return -1;
  kins_type = switchkins_type;
  return 0;
}

int kinematicsForward(const double* joint, EmcPose* world, const KINEMATICS_FORWARD_FLAGS* fflags,
                      KINEMATICS_INVERSE_FLAGS* iflags) {
  double w[3] = {joint[0], joint[1], joint[2]};
  (void)fflags;
  (void)iflags;
  if (kins_type == 1 && trueaxis_kins_forward(joint, joint[3], joint[4], w) != 0) return -1;
  world->tran.x = w[0];
  world->tran.y = w[1];
  world->tran.z = w[2];
  world->a = joint[3];
  world->b = 0.0;
  world->c = joint[4];
  world->u = 0.0;
  world->v = 0.0;
  world->w = 0.0;
  return 0;
}

int kinematicsInverse(const EmcPose* world, double* joint, const KINEMATICS_INVERSE_FLAGS* iflags,
                      KINEMATICS_FORWARD_FLAGS* fflags) {
  const double w[3] = {world->tran.x, world->tran.y, world->tran.z};
  double j[3] = {w[0], w[1], w[2]};
  (void)iflags;
  (void)fflags;
  if (kins_type == 1 && trueaxis_kins_inverse(w, world->a, world->c, j) != 0) return -1;
  joint[0] = j[0];
  joint[1] = j[1];
  joint[2] = j[2];
  joint[3] = world->a;
  joint[4] = world->c;
  return 0;
}

EXPORT_SYMBOL(kinematicsType);
EXPORT_SYMBOL(kinematicsSwitchable);
EXPORT_SYMBOL(kinematicsSwitch);
EXPORT_SYMBOL(kinematicsForward);
EXPORT_SYMBOL(kinematicsInverse);
