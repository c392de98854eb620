/* trueaxis_kins: LinuxCNC kinematics for an XYZAC cradle machine on its
   calibrated axes (cradle_kinematics.hpp through kins_api.h), a real-time
   module for LinuxCNC 2.9 (uspace). In the ini:
       [KINS]
       KINEMATICS = trueaxis_kins table=/path/to/m3.table home=N
       JOINTS = 5
   (home=: the machine's home identity, the module's #904: a table measured
   under another is refused, cradle_kinematics.hpp convention 8.)
   `table` is the file `trueaxis-calibrate rigidity --store --linuxcnc-kins`
   (or `trueaxis-calibrate linuxcnc-kins rigidity`) writes from the
   controller's stored M3 table. Without `table` the machine is the ideal
   cradle; a `table` that cannot be read or does not check stops LinuxCNC's
   start with one line naming the file and why: a machine never runs on ideal
   axes in place of a calibration it was given. `spindle=FILE` likewise loads
   the stored M4 model (`trueaxis-calibrate spindle --store --linuxcnc-kins`).
   The pin trueaxis_kins.tool-offset is the active tool's length offset:
   net motion.tooloffset.z to it. LinuxCNC adds that offset to the world's Z
   (the table's), where on a tilted table the tool does not point; the module
   takes it back off and applies it along the tool, the machine's Z, at the
   commanded A and C (as xyzac-trt-kins' tool-offset pin): with G43 the tool's
   tip is the controlled point, with G49 the gauge line. While the pin
   trueaxis_kins.tip-enable is true, the tool tip's error at
   trueaxis_kins.spindle-angle (deg, the oriented spindle's, M19) and that
   tool length (with trueaxis_kins.tip-mean, its mean over a revolution, for
   a rotating tool) is taken off the joints' X, Y, Z, so that the tip lands
   where the program says. The function trueaxis_kins.update (addf it to the
   servo thread) ramps the correction applied towards that, at most
   trueaxis_kins.tip-ramp um a servo period (0.5 at the start), and shows
   it: tip-x, tip-y, tip-z (mm), tip-settled (the pins' correction reached;
   a program waits on it with M66 before a touch). The correction on without
   a model, at a tool length the model refuses (below 0), or with update
   never run (in no thread), is a kinematics error (tip-fault), not an
   uncorrected move.
   On an inch machine give linear_units=inch: the tables are in mm, and the
   world, the joints and the tool offset are converted; without it an inch
   machine's offsets would be read as mm.
   Without a table the cradle is ideal about the nominal pivot: pivot=X,Y,Z
   (the C axis' point at A = 0) and a_offset=DY,DZ (the A axis' from it), as
   xyzac-trt-kins' rot-point and offsets take them; a table's measured axes
   replace them.
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
static char* spindle = 0;
RTAPI_MP_STRING(spindle, "the M4 model file (trueaxis-calibrate spindle --store --linuxcnc-kins); absent: no tip correction");
static char* home = 0;
RTAPI_MP_STRING(home, "the machine's home identity (the module's #904); a table measured under another is refused; absent: 0");
static char* pivot = 0;
RTAPI_MP_STRING(pivot, "X,Y,Z: the ideal cradle's C axis at A = 0 (xyzac-trt-kins' x/y/z-rot-point); absent: the origin");
static char* a_offset = 0;
RTAPI_MP_STRING(a_offset, "DY,DZ: the ideal cradle's A axis from the pivot (xyzac-trt-kins' y-offset, z-offset); absent: 0,0");
static char* linear_units = 0;
RTAPI_MP_STRING(linear_units, "mm (absent) or inch, as [TRAJ] LINEAR_UNITS: the tables are in mm");

static int comp_id = -1;
static int kins_type = 0; /* switchkins type: 0 identity, 1 the cradle */

/* The tool's pins (conventions 5-7 of cradle_kinematics.hpp). */
struct tip_pins {
  hal_bit_t* enable;
  hal_bit_t* mean;          /* the mean over a revolution, for a rotating tool */
  hal_float_t* angle_deg;
  hal_float_t* tool_offset;
  hal_float_t* ramp_um;     /* at most this far a servo period */
  hal_bit_t* settled;       /* out: the correction applied is the pins' */
  hal_bit_t* fault;         /* out: the pins ask for a correction the model refuses: the kinematics stop motion */
  hal_float_t* applied[3];  /* out: the correction applied, mm */
};
static struct tip_pins* tip = 0;
static double applied_mm[3] = {0.0, 0.0, 0.0};
static int updates = 0; /* trueaxis_kins.update's runs (capped): 0, the function is in no thread */

static double tool_offset(void) { return tip != 0 ? *tip->tool_offset : 0.0; }

/* A servo period: the correction ramped towards the pins' (convention 7). */
static void update(void* arg, long period) {
  double target[3] = {0.0, 0.0, 0.0};
  int i;
  (void)arg;
  (void)period;
  if (tip == 0) return;
  if (*tip->enable) {
    if (trueaxis_kins_tip_target(*tip->mean ? 2 : 1, *tip->angle_deg, *tip->tool_offset, target) != 0) {
      *tip->fault = 1; /* no move on a correction it cannot give: the kinematics fail */
      *tip->settled = 0;
      return;
    }
  }
  *tip->fault = 0;
  *tip->settled = trueaxis_kins_tip_ramp(target, 0.001 * *tip->ramp_um, applied_mm) == 1;
  for (i = 0; i < 3; ++i) *tip->applied[i] = applied_mm[i];
  if (updates < 2) ++updates;
}

/* The kinematics' refusal: a fault, or the correction on while update runs in no thread. */
static int tip_refused(void) { return tip != 0 && (*tip->fault || (*tip->enable && updates == 0)); }

int rtapi_app_main(void) {
  comp_id = hal_init("trueaxis_kins");
  if (comp_id < 0) return comp_id;
  if (linear_units != 0 && linear_units[0] != '\0') {
    const char* why = "";
    if (trueaxis_kins_set_linear_units(linear_units, &why) != 0) {
      rtapi_print_msg(RTAPI_MSG_ERR, "trueaxis_kins: linear_units=%s: %s\n", linear_units, why);
      hal_exit(comp_id);
      return -EINVAL;
    }
  }
  {
    const char* why = "";
    if (trueaxis_kins_set_pivot(pivot, a_offset, &why) != 0) {
      rtapi_print_msg(RTAPI_MSG_ERR, "trueaxis_kins: pivot=%s a_offset=%s: %s\n", pivot ? pivot : "",
                      a_offset ? a_offset : "", why);
      hal_exit(comp_id);
      return -EINVAL;
    }
  }
  {
    const char* why = "";
    if (trueaxis_kins_set_home(home, &why) != 0) {
      rtapi_print_msg(RTAPI_MSG_ERR, "trueaxis_kins: home=%s: %s\n", home ? home : "", why);
      hal_exit(comp_id);
      return -EINVAL;
    }
  }
  if (table != 0 && table[0] != '\0') {
    const char* why = "";
    if (trueaxis_kins_load(table, &why) != 0) {
      if (trueaxis_kins_file_home() != trueaxis_kins_home()) {
        rtapi_print_msg(RTAPI_MSG_ERR, "trueaxis_kins: table %s: measured under home identity %u, this machine's "
                        "home=%u: %s\n", table, trueaxis_kins_file_home(), trueaxis_kins_home(), why);
        hal_exit(comp_id);
        return -EINVAL;
      }
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
  if (spindle != 0 && spindle[0] != '\0') {
    const char* why = "";
    if (trueaxis_kins_load_spindle(spindle, &why) != 0) {
      rtapi_print_msg(RTAPI_MSG_ERR,
                      "trueaxis_kins: spindle %s: %s; the machine does not start without the tip correction it "
                      "was given (write the file again: trueaxis-calibrate spindle --store --linuxcnc-kins FILE)\n",
                      spindle, why);
      hal_exit(comp_id);
      return -EINVAL;
    }
  }
  {
    /* The pins are published to the kinematics only once they all exist. */
    struct tip_pins* pins = hal_malloc(sizeof *pins);
    if (pins == 0 || hal_pin_bit_new("trueaxis_kins.tip-enable", HAL_IN, &pins->enable, comp_id) != 0 ||
        hal_pin_bit_new("trueaxis_kins.tip-mean", HAL_IN, &pins->mean, comp_id) != 0 ||
        hal_pin_float_new("trueaxis_kins.spindle-angle", HAL_IN, &pins->angle_deg, comp_id) != 0 ||
        hal_pin_float_new("trueaxis_kins.tool-offset", HAL_IN, &pins->tool_offset, comp_id) != 0 ||
        hal_pin_float_new("trueaxis_kins.tip-ramp", HAL_IN, &pins->ramp_um, comp_id) != 0 ||
        hal_pin_bit_new("trueaxis_kins.tip-settled", HAL_OUT, &pins->settled, comp_id) != 0 ||
        hal_pin_bit_new("trueaxis_kins.tip-fault", HAL_OUT, &pins->fault, comp_id) != 0 ||
        hal_pin_float_new("trueaxis_kins.tip-x", HAL_OUT, &pins->applied[0], comp_id) != 0 ||
        hal_pin_float_new("trueaxis_kins.tip-y", HAL_OUT, &pins->applied[1], comp_id) != 0 ||
        hal_pin_float_new("trueaxis_kins.tip-z", HAL_OUT, &pins->applied[2], comp_id) != 0 ||
        hal_export_funct("trueaxis_kins.update", update, 0, 1, 0, comp_id) != 0) {
      rtapi_print_msg(RTAPI_MSG_ERR, "trueaxis_kins: its pins and function could not be made\n");
      hal_exit(comp_id);
      return -ENOMEM;
    }
    *pins->ramp_um = 0.5; /* 0.5 um a period: 0.5 mm/s at 1 kHz (kDefaultTipRampMm) */
    *pins->settled = 1;
    hal_ready(comp_id);
    tip = pins;
  }
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
  double w[3];
  (void)fflags;
  (void)iflags;
  if (tip_refused() || trueaxis_kins_to_world_with(kins_type, joint, joint[3], joint[4], tool_offset(), applied_mm, w) != 0) {
    return -1;
  }
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
  double j[3];
  (void)iflags;
  (void)fflags;
  if (tip_refused() || trueaxis_kins_to_joints_with(kins_type, w, world->a, world->c, tool_offset(), applied_mm, j) != 0) {
    return -1;
  }
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
