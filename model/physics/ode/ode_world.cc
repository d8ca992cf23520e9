#include "model/physics/ode/ode_world.h"

#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "base/demand.h"
#include "model/core/error.h"
#include "model/physics/material_table.h"
#include "model/physics/ode/ode_joints.h"

namespace orcs::physics {
namespace {

static_assert(sizeof(dReal) == sizeof(double), "orcs needs ODE in double precision");

// Angular motor constants of the original (/ODEJoint/..., spec/aseries.md §6a, §8).
constexpr double kMotorCfm = 1e-5;
constexpr double kMotorStopErp = 0.2;
constexpr double kMotorStopCfm = 1e-5;
constexpr double kMotorBounce = 0.0;
constexpr double kMotorFudgeFactor = 1.0;

// Formats ODE's printf-style message and throws. ODE declares its error and debug functions noreturn; ODE is
// compiled as C++, so the exception unwinds through it back into OdeWorld::Step (or the constructor).
[[noreturn]] void ThrowOdeMessage(const char* kind, int errnum, const char* format, va_list args) {
  std::array<char, 1024> text{};
  std::vsnprintf(text.data(), text.size(), format, args);
  throw PhysicsError(std::string("ODE ") + kind + " " + std::to_string(errnum) + ": " + text.data());
}

[[noreturn]] void OnOdeError(int errnum, const char* format, va_list args) {
  ThrowOdeMessage("error", errnum, format, args);
}

[[noreturn]] void OnOdeDebug(int errnum, const char* format, va_list args) {
  ThrowOdeMessage("debug trap", errnum, format, args);
}

// ODE's non-fatal messages (e.g. "LCP internal error"): the step still completes, and the instability check
// catches a world that went bad. Ignored so that thousands of evaluations do not flood the worker's stderr.
void OnOdeMessage(int /*errnum*/, const char* /*format*/, va_list /*args*/) {}

// ODE's per-thread data (collision caches), allocated on a thread's first use and freed when it ends.
struct OdeThreadData {
  OdeThreadData() {
    if (dAllocateODEDataForThread(dAllocateMaskAll) == 0) {
      throw PhysicsError("ODE could not allocate its per-thread data");
    }
  }
  ~OdeThreadData() { dCleanupODEAllDataForThread(); }
  OdeThreadData(const OdeThreadData&) = delete;
  OdeThreadData& operator=(const OdeThreadData&) = delete;
};

// Initialises ODE once per process and once per calling thread. Cheap after the first call.
void EnsureOdeReady() {
  static std::once_flag once;
  std::call_once(once, [] {
    dInitODE2(0);
    dSetErrorHandler(&OnOdeError);
    dSetDebugHandler(&OnOdeDebug);
    dSetMessageHandler(&OnOdeMessage);
  });
  thread_local OdeThreadData thread_data;
  (void)thread_data;
}

// dWorldQuickStep shuffles its constraints with ODE's one process-wide random generator (dRand), so a QuickStep
// run would depend on what the process stepped before it. Each world keeps its own generator state and steps with
// it under this lock, which keeps threads from interleaving their states (uncontended: one simulation per thread).
std::mutex& QuickStepMutex() {
  static std::mutex mutex;
  return mutex;
}

void ToOde(const Eigen::Quaterniond& q, dQuaternion out) {
  out[0] = q.w();  // ODE stores quaternions as (w, x, y, z)
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}

bool IsIdentity(const Eigen::Quaterniond& q) { return q.w() == 1.0 && q.vec().isZero(0.0); }

void* IndexToData(int index) { return reinterpret_cast<void*>(static_cast<std::intptr_t>(index)); }
int DataToIndex(void* data) { return static_cast<int>(reinterpret_cast<std::intptr_t>(data)); }

// NERD's mass rule (spec/aseries.md §2b): a uniform solid of the main geom's shape carrying the total mass,
// centred at the body origin whatever the main geom's offset; only its rotation turns the inertia.
dMass MainGeomMass(const GeomDescription& geom, double total_mass) {
  dMass mass;
  dMassSetZero(&mass);
  const Eigen::Vector3d& s = geom.size;
  switch (geom.shape) {
    case Shape::kBox:
      dMassSetBoxTotal(&mass, total_mass, s.x(), s.y(), s.z());
      break;
    case Shape::kSphere:
      dMassSetSphereTotal(&mass, total_mass, s.x());
      break;
    case Shape::kCapsule:
      dMassSetCapsuleTotal(&mass, total_mass, 3, s.x(), s.y());  // 3: cylinder along the local z axis
      break;
    case Shape::kPlane:
      ORCS_UNREACHABLE("PhysicsModel rejects planes on dynamic bodies");
      break;
  }
  if (!IsIdentity(geom.rotation)) {
    dQuaternion q;
    ToOde(geom.rotation, q);
    dMatrix3 rotation;
    dRfromQ(rotation, q);
    dMassRotate(&mass, rotation);
  }
  return mass;
}

class OdeWorld final : public PhysicsWorld {
 public:
  explicit OdeWorld(std::shared_ptr<const PhysicsModel> model);
  ~OdeWorld() override { Destroy(); }
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  void Reset() override;
  StepStatus Step(double dt, const PhysicsParameters& parameters) override;
  const std::vector<Contact>& contacts() const override { return contacts_; }
  void SetReportExcludedContacts(bool report) override { report_excluded_ = report; }
  BodyState body_state(int body) const override;
  void SetBodyState(int body, const BodyState& state) override;
  double joint_angle(int joint) const override;
  double joint_rate(int joint) const override;
  double joint_motor_torque(int joint) const override;
  void SetJointMotor(int joint, double velocity, double max_torque) override;
  void SetJointFriction(int joint, double max_torque) override;
  void AddJointTorque(int joint, double torque) override;
  void SetJointMotorCompliance(int joint, double compliance) override;
  void AddBodyInertia(int body, const Eigen::Vector3d& axis_in_body, double inertia) override;
  const std::string& last_error() const override { return last_error_; }
  const PhysicsModel& model() const override { return *model_; }

 private:
  void Build();
  void BuildGuarded();
  void Destroy();
  void BuildBody(int body);
  dGeomID BuildGeom(const BodyDescription& body, const GeomDescription& geom, dBodyID body_id);
  void BuildJoint(int joint);
  dJointID BuildMotor(int joint, dBodyID body1, dBodyID body2, const Eigen::Vector3d& axis);

  void ApplyParameters(const PhysicsParameters& parameters);
  static void NearCallback(void* data, dGeomID o1, dGeomID o2);
  void Collide(dGeomID o1, dGeomID o2);
  double ChooseFriction(const dContactGeom& point, dBodyID b1, dBodyID b2, const ContactMaterial& material) const;
  void AddContactJoint(const dContactGeom& point, dBodyID b1, dBodyID b2, const ContactMaterial& material);
  StepStatus CheckStability(const PhysicsParameters& parameters) const;
  bool IsHinge(int joint) const { return model_->joint(joint).type == JointType::kHinge; }

  // Motor and brake rows (docs/model.md): see StepExact.
  enum class RowCase {
    kTwoRows,       // both rows, as built
    kBrakeSliding,  // brake at its limit against the rate's sign: the motor row plus the brake as a fixed torque
    kBothFree,      // neither at its limit: one unbounded row with the pair's combined target and CFM
  };
  struct MotorRows {  // per model joint
    double velocity = 0.0;       // angular motor target v, rad/s
    double max_torque = 0.0;     // angular motor FMax τ ≥ 0, N·m
    double friction = 0.0;       // brake FMax f ≥ 0, N·m
    double cfm = kMotorCfm;      // angular motor CFM c1 (SetJointMotorCompliance), rad/s per N·m
    double last_velocity = 0.0;  // v of the last step
    double last_rate = 0.0;      // joint rate u after the last step, rad/s
    bool has_last = false;       // a StepExact has recorded last_velocity and last_rate since the build
  };
  struct CombinedJoint {  // per motorised hinge, during one StepExact
    int joint = -1;
    RowCase row_case = RowCase::kTwoRows;
    double sign = 0.0;  // kBrakeSliding: the sign of u
    dVector3 axis{};    // the hinge axis before the step: the direction both rows constrain
  };
  struct SavedBody {  // what a repeated dWorldStep needs back
    dVector3 position{}, linear_velocity{}, angular_velocity{}, force{}, torque{};
    dQuaternion orientation{};
  };
  int StepExact(double dt, bool combine);
  RowCase PredictRowCase(int joint, double& sign) const;
  void CombineRows(const CombinedJoint& joint);
  void SeparateRows(const CombinedJoint& joint);
  bool RowCaseHeld(const CombinedJoint& joint) const;
  void ReportMotorShare(const CombinedJoint& joint);
  double RateAbout(int joint, const dVector3 axis) const;
  void SaveBodies();
  void RestoreBodies();

  std::shared_ptr<const PhysicsModel> model_;
  dWorldID world_ = nullptr;
  dThreadingImplementationID threading_ = nullptr;  // the world's own step threading (Build explains why)
  dSpaceID space_ = nullptr;
  dJointGroupID contact_group_ = nullptr;
  std::vector<dBodyID> bodies_;   // per model body; nullptr for static bodies
  std::vector<dGeomID> geoms_;    // per model geom
  std::vector<dJointID> joints_;  // per model joint: hinge or fixed joint
  std::vector<dJointID> motors_;  // per model joint: the AMotor of a motorised hinge, else nullptr
  // Per model joint: what ODE reports the AMotor applied in the last step. Sized once: ODE keeps pointers.
  std::vector<dJointFeedback> motor_feedback_;
  std::vector<MotorRows> motor_rows_;    // per model joint
  std::vector<CombinedJoint> combined_;  // per motorised hinge, of the running step
  std::vector<SavedBody> saved_bodies_;  // per model body
  unsigned long quickstep_seed_ = 0;     // this world's state of ODE's generator (QuickStepMutex)
  std::vector<BodyFrictionParameters> body_friction_;  // per model body, for unknown materials
  std::vector<Contact> contacts_;                       // of the last step; capacity is kept across steps
  bool report_excluded_ = true;                         // SetReportExcludedContacts
  std::array<dContactGeom, PhysicsParameters::kMaxContactPoints> contact_buffer_{};  // dCollide's output
  const PhysicsParameters* parameters_ = nullptr;  // those of the running Step, read by the collision callback
  StepStatus status_ = StepStatus::kOk;            // sticky until Reset
  std::string last_error_;
};

OdeWorld::OdeWorld(std::shared_ptr<const PhysicsModel> model) : model_(std::move(model)) {
  EnsureOdeReady();
  motor_feedback_.resize(static_cast<std::size_t>(model_->joint_count()));
  body_friction_.reserve(model_->body_count());
  for (int b = 0; b < model_->body_count(); ++b) {
    const BodyDescription& body = model_->body(b);
    body_friction_.push_back({body.static_friction, body.dynamic_friction, body.elasticity});
  }
  // Enough for every geom to touch a few others; grows (once) if a scene needs more.
  contacts_.reserve(static_cast<std::size_t>(std::max(64, 8 * model_->geom_count())));
  BuildGuarded();
}

void OdeWorld::Reset() {
  // Rebuilding from scratch, rather than restoring poses, also restores ODE's internal orders (space list,
  // joint lists, warm starts), which is what makes reruns bit-identical.
  Destroy();
  status_ = StepStatus::kEngineError;  // stays so if the rebuild throws: Step refuses an empty world
  BuildGuarded();
  status_ = StepStatus::kOk;
  last_error_.clear();
  contacts_.clear();
}

// ODE rejects nothing that PhysicsModel accepted, but if it does, the half-built world must not leak.
void OdeWorld::BuildGuarded() {
  try {
    Build();
  } catch (...) {
    Destroy();
    throw;
  }
}

void OdeWorld::Build() {
  world_ = dWorldCreate();
  // A threading implementation of the world's own: ODE's default one is shared by every world of the process and
  // guarded by no lock, so two threads stepping two worlds at once (orcs-robot's twin beside the servo-bus
  // emulator's simulated shafts) corrupted its job list, and a step never returned. Self-threaded: the same jobs
  // in the same order, on the calling thread.
  threading_ = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(world_, dThreadingImplementationGetFunctions(threading_), threading_);
  // Joint stops and motors take the world's ERP/CFM at creation. Use the original's values (0.2 / 1e-5), not
  // ODE's double-precision default CFM (1e-10).
  const PhysicsParameters defaults;
  dWorldSetERP(world_, defaults.erp);
  dWorldSetCFM(world_, defaults.cfm);
  space_ = dSimpleSpaceCreate(nullptr);
  contact_group_ = dJointGroupCreate(0);

  bodies_.assign(model_->body_count(), nullptr);
  geoms_.assign(model_->geom_count(), nullptr);
  joints_.assign(model_->joint_count(), nullptr);
  motors_.assign(model_->joint_count(), nullptr);
  motor_rows_.assign(model_->joint_count(), MotorRows{});
  combined_.clear();
  combined_.reserve(model_->joint_count());
  saved_bodies_.resize(model_->body_count());
  quickstep_seed_ = 0;
  for (int b = 0; b < model_->body_count(); ++b) BuildBody(b);
  for (int j = 0; j < model_->joint_count(); ++j) BuildJoint(j);
}

void OdeWorld::Destroy() {
  // Contacts first, then the space (destroys its geoms), then the world (destroys bodies and joints).
  if (contact_group_ != nullptr) dJointGroupDestroy(contact_group_);
  if (space_ != nullptr) dSpaceDestroy(space_);
  if (world_ != nullptr) dWorldDestroy(world_);
  if (threading_ != nullptr) dThreadingFreeImplementation(threading_);  // after the world that used it
  threading_ = nullptr;
  contact_group_ = nullptr;
  space_ = nullptr;
  world_ = nullptr;
  std::fill(bodies_.begin(), bodies_.end(), nullptr);
  std::fill(geoms_.begin(), geoms_.end(), nullptr);
  std::fill(joints_.begin(), joints_.end(), nullptr);
  std::fill(motors_.begin(), motors_.end(), nullptr);
}

void OdeWorld::BuildBody(int b) {
  const BodyDescription& body = model_->body(b);
  dBodyID id = nullptr;
  if (body.dynamic) {
    id = dBodyCreate(world_);
    dBodySetPosition(id, body.position.x(), body.position.y(), body.position.z());
    dQuaternion q;
    ToOde(body.orientation, q);
    dBodySetQuaternion(id, q);
    dMass mass = MainGeomMass(body.geoms[0], model_->total_mass(b));
    if (!body.inertia.isZero(0.0)) {  // its own inertia, given: the rule's is replaced
      dMassSetParameters(&mass, model_->total_mass(b), 0, 0, 0, body.inertia.x(), body.inertia.y(), body.inertia.z(), 0, 0, 0);
    }
    dBodySetMass(id, &mass);
  }
  bodies_[b] = id;
  const int first = model_->first_geom(b);
  for (int g = 0; g < static_cast<int>(body.geoms.size()); ++g) {
    dGeomID geom = BuildGeom(body, body.geoms[g], id);
    dGeomSetData(geom, IndexToData(first + g));  // the collision callback maps ODE geoms back to model geoms
    geoms_[first + g] = geom;
  }
}

dGeomID OdeWorld::BuildGeom(const BodyDescription& body, const GeomDescription& geom, dBodyID body_id) {
  const Eigen::Vector3d& s = geom.size;
  const Eigen::Quaterniond world_rotation = body.orientation * geom.rotation;
  const Eigen::Vector3d world_position = body.position + body.orientation * geom.offset;
  dGeomID id = nullptr;
  switch (geom.shape) {
    case Shape::kBox:
      id = dCreateBox(space_, s.x(), s.y(), s.z());
      break;
    case Shape::kSphere:
      id = dCreateSphere(space_, s.x());
      break;
    case Shape::kCapsule:
      id = dCreateCapsule(space_, s.x(), s.y());
      break;
    case Shape::kPlane: {
      // Non-placeable in ODE: the plane n·p = d, through the geom's world position.
      const Eigen::Vector3d normal = world_rotation * Eigen::Vector3d::UnitY();
      id = dCreatePlane(space_, normal.x(), normal.y(), normal.z(), normal.dot(world_position));
      break;
    }
  }
  if (geom.shape != Shape::kPlane) {
    dQuaternion q;
    if (body_id != nullptr) {
      dGeomSetBody(id, body_id);
      // Offsets cost ODE a transform per step; only set them where they are not the identity.
      if (!geom.offset.isZero(0.0)) dGeomSetOffsetPosition(id, geom.offset.x(), geom.offset.y(), geom.offset.z());
      if (!IsIdentity(geom.rotation)) {
        ToOde(geom.rotation, q);
        dGeomSetOffsetQuaternion(id, q);
      }
    } else {
      dGeomSetPosition(id, world_position.x(), world_position.y(), world_position.z());
      ToOde(world_rotation, q);
      dGeomSetQuaternion(id, q);
    }
  }
  if (!geom.collides) {
    // Penetrable: ODE's broad phase never pairs a geom whose category and collide bits are both 0.
    dGeomSetCategoryBits(id, 0);
    dGeomSetCollideBits(id, 0);
  }
  return id;
}

void OdeWorld::BuildJoint(int j) {
  const JointDescription& joint = model_->joint(j);
  dBodyID body1 = bodies_[model_->joint_body1(j)];
  const int b2 = model_->joint_body2(j);
  dBodyID body2 = b2 >= 0 ? bodies_[b2] : nullptr;  // nullptr attaches to the static world

  if (joint.type == JointType::kFixed) {
    joints_[j] = CreateFixedJoint(world_, body1, body2);
    return;
  }
  // The original creates the motor before the hinge; the order fixes ODE's row order, so keep it.
  if (joint.motorised) motors_[j] = BuildMotor(j, body1, body2, joint.axis);
  // The hinge's own motor is the joint friction: a brake towards zero rate, off until SetJointFriction.
  joints_[j] = CreateHinge(world_, body1, body2, joint);
}

// A one-axis angular motor about the hinge axis, fixed in body 1: it constrains the same relative rate
// (ω1 − ω2)·axis that dJointGetHingeAngleRate reports, so SetJointMotor's velocity is the joint rate.
dJointID OdeWorld::BuildMotor(int joint, dBodyID body1, dBodyID body2, const Eigen::Vector3d& axis) {
  dJointID motor = dJointCreateAMotor(world_, nullptr);
  dJointAttach(motor, body1, body2);
  motor_feedback_[joint] = dJointFeedback{};
  dJointSetFeedback(motor, &motor_feedback_[joint]);
  dJointSetAMotorMode(motor, dAMotorUser);
  dJointSetAMotorNumAxes(motor, 1);
  dJointSetAMotorAxis(motor, 0, 1, axis.x(), axis.y(), axis.z());
  dJointSetAMotorParam(motor, dParamVel, 0.0);
  dJointSetAMotorParam(motor, dParamFMax, 0.0);  // off until SetJointMotor
  dJointSetAMotorParam(motor, dParamCFM, kMotorCfm);
  dJointSetAMotorParam(motor, dParamStopERP, kMotorStopErp);
  dJointSetAMotorParam(motor, dParamStopCFM, kMotorStopCfm);
  dJointSetAMotorParam(motor, dParamBounce, kMotorBounce);
  dJointSetAMotorParam(motor, dParamFudgeFactor, kMotorFudgeFactor);
  return motor;
}

StepStatus OdeWorld::Step(double dt, const PhysicsParameters& parameters) {
  if (status_ != StepStatus::kOk) return status_;
  contacts_.clear();
  try {
    EnsureOdeReady();  // the world may be stepped on another thread than the one that made it
    ApplyParameters(parameters);
    parameters_ = &parameters;
    // ODE writes feedback only for joints that add rows; a motor with no torque adds none and would keep
    // reporting the torque of its last active step.
    for (dJointFeedback& feedback : motor_feedback_) feedback = dJointFeedback{};
    dSpaceCollide(space_, this, &OdeWorld::NearCallback);
    int stepped = 0;
    if (parameters.solver == Solver::kQuickStep) {
      for (MotorRows& rows : motor_rows_) rows.has_last = false;  // StepExact predicts from its own steps only
      const std::lock_guard<std::mutex> lock(QuickStepMutex());
      dRandSetSeed(quickstep_seed_);
      stepped = dWorldQuickStep(world_, dt);
      quickstep_seed_ = dRandGetSeed();
    } else {
      stepped = StepExact(dt, parameters.combine_motor_rows);
    }
    dJointGroupEmpty(contact_group_);
    if (stepped == 0) throw PhysicsError("ODE could not allocate memory for the step");
  } catch (const PhysicsError& error) {
    last_error_ = error.what();
    status_ = StepStatus::kEngineError;
    return status_;
  }
  status_ = CheckStability(parameters);
  return status_;
}

// All cheap setters; doing them every step lets the parameters change between any two steps.
void OdeWorld::ApplyParameters(const PhysicsParameters& p) {
  dWorldSetGravity(world_, p.gravity.x(), p.gravity.y(), p.gravity.z());
  dWorldSetERP(world_, p.erp);
  dWorldSetCFM(world_, p.cfm);
  dWorldSetContactSurfaceLayer(world_, p.contact_surface_layer);
  dWorldSetContactMaxCorrectingVel(world_, p.contact_max_correcting_velocity);
  if (p.solver == Solver::kQuickStep) dWorldSetQuickStepNumIterations(world_, std::max(1, p.quickstep_iterations));
}

void OdeWorld::NearCallback(void* data, dGeomID o1, dGeomID o2) { static_cast<OdeWorld*>(data)->Collide(o1, o2); }

void OdeWorld::Collide(dGeomID o1, dGeomID o2) {
  const int g1 = DataToIndex(dGeomGetData(o1));
  const int g2 = DataToIndex(dGeomGetData(o2));
  const GeomInfo& info1 = model_->geom(g1);
  const GeomInfo& info2 = model_->geom(g2);
  if (info1.body == info2.body) return;  // geoms of one body never touch (ODE skips only dynamic ones)
  dBodyID b1 = bodies_[info1.body];
  dBodyID b2 = bodies_[info2.body];
  if (b1 == nullptr && b2 == nullptr) return;  // two static bodies: nothing can move
  const bool excluded = model_->contact_excluded(info1.body, info2.body);
  if (excluded && !report_excluded_) return;
  const PhysicsParameters& p = *parameters_;
  const int max_points = std::clamp(p.max_contact_points, 1, PhysicsParameters::kMaxContactPoints);
  const int found = dCollide(o1, o2, max_points, contact_buffer_.data(), sizeof(dContactGeom));
  if (found == 0) return;

  const ContactMaterial material = MaterialTable::Lookup(info1.material, info2.material, body_friction_[info1.body],
                                                         body_friction_[info2.body], p.custom1, p.custom2);
  for (int i = 0; i < found; ++i) {
    const dContactGeom& point = contact_buffer_[i];
    if (std::abs(point.depth) < p.min_contact_depth) continue;
    Contact& contact = contacts_.emplace_back();
    contact.geom1 = g1;
    contact.geom2 = g2;
    contact.body1 = info1.body;
    contact.body2 = info2.body;
    contact.position = {point.pos[0], point.pos[1], point.pos[2]};
    contact.normal = {point.normal[0], point.normal[1], point.normal[2]};
    contact.depth = point.depth;
    contact.excluded = excluded;
    if (!excluded) AddContactJoint(point, b1, b2, material);
  }
}

// Static coefficient while the surfaces do not slide against each other at the contact point, else the scaled
// dynamic one (the documented replacement of the original's unset "motion" fields, spec/aseries.md §7).
double OdeWorld::ChooseFriction(const dContactGeom& point, dBodyID b1, dBodyID b2,
                                const ContactMaterial& material) const {
  dVector3 v1 = {0.0, 0.0, 0.0, 0.0};
  dVector3 v2 = {0.0, 0.0, 0.0, 0.0};
  if (b1 != nullptr) dBodyGetPointVel(b1, point.pos[0], point.pos[1], point.pos[2], v1);
  if (b2 != nullptr) dBodyGetPointVel(b2, point.pos[0], point.pos[1], point.pos[2], v2);
  const Eigen::Vector3d relative(v1[0] - v2[0], v1[1] - v2[1], v1[2] - v2[2]);
  const Eigen::Vector3d normal(point.normal[0], point.normal[1], point.normal[2]);
  const Eigen::Vector3d tangential = relative - relative.dot(normal) * normal;
  const PhysicsParameters& p = *parameters_;
  return tangential.squaredNorm() < p.static_friction_speed * p.static_friction_speed
             ? material.static_friction
             : material.dynamic_friction * p.friction_scaling;
}

void OdeWorld::AddContactJoint(const dContactGeom& point, dBodyID b1, dBodyID b2, const ContactMaterial& material) {
  CreateContactJoint(world_, contact_group_, point, b1, b2, ChooseFriction(point, b1, b2, material), material,
                     *parameters_);
}

// A motorised hinge carries two constraint rows on the same axis: the angular motor (rate v, |torque| ≤ τ, CFM c1)
// and the hinge's friction brake (rate 0, |torque| ≤ f, CFM c2). Identical rows make the pivoting LCP solver of
// dWorldStep shuttle between them: for the A-Series the 21 pairs more than double the cost of a step. With u the
// joint rate after the step, the rows satisfy u = v − c1·λ1 while the motor is inside its limits and u = −c2·λ2
// while the brake is, so which of them is at its limit follows from u alone, and in the usual cases one row does
// the work of both:
//   kBrakeSliding  brake at its limit, λ2 = −f·sign(u): the motor row, plus the brake as a fixed torque;
//   kBothFree      neither at its limit: one unbounded row u = c2·v/(c1+c2) − c1·c2/(c1+c2)·(λ1 + λ2).
// Each hinge's case is predicted from the last step. After the step, u shows whether every prediction held; the
// solution then satisfies the two-row problem's conditions too. If one did not hold, the bodies are put back and
// the step is repeated with both rows everywhere. Results differ from two rows by rounding and by the path the
// pivoting takes through ODE's approximate friction bounds (A-Series, 10 s: below 2e-9 m); they stay deterministic.
int OdeWorld::StepExact(double dt, bool combine) {
  combined_.clear();
  bool any = false;
  for (int j = 0; j < model_->joint_count(); ++j) {
    if (motors_[j] == nullptr) continue;
    CombinedJoint& joint = combined_.emplace_back();
    joint.joint = j;
    dJointGetHingeAxis(joints_[j], joint.axis);
    if (combine) joint.row_case = PredictRowCase(j, joint.sign);
    any = any || joint.row_case != RowCase::kTwoRows;
  }
  if (any) {
    SaveBodies();
    for (const CombinedJoint& joint : combined_) CombineRows(joint);
  }
  int stepped = dWorldStep(world_, dt);
  if (any) {
    bool held = true;
    for (const CombinedJoint& joint : combined_) {
      SeparateRows(joint);
      held = held && RowCaseHeld(joint);
    }
    if (!held && stepped != 0) {
      RestoreBodies();
      stepped = dWorldStep(world_, dt);
    } else if (held) {
      for (const CombinedJoint& joint : combined_) {
        if (joint.row_case == RowCase::kBothFree) ReportMotorShare(joint);
      }
    }
  }
  for (const CombinedJoint& joint : combined_) {
    MotorRows& rows = motor_rows_[joint.joint];
    rows.last_velocity = rows.velocity;
    rows.last_rate = RateAbout(joint.joint, joint.axis);
    rows.has_last = true;
  }
  return stepped;
}

OdeWorld::RowCase OdeWorld::PredictRowCase(int joint, double& sign) const {
  const MotorRows& rows = motor_rows_[joint];
  if (!rows.has_last || rows.max_torque <= 0.0 || rows.friction <= 0.0) return RowCase::kTwoRows;  // < 2 rows
  dJointID hinge = joints_[joint];
  const double c1 = dJointGetAMotorParam(motors_[joint], dParamCFM);
  const double c2 = dJointGetHingeParam(hinge, dParamCFM);
  // At a stop ODE makes the hinge row the stop and applies the brake as a torque of its own (addLimot): keep it.
  const double angle = dJointGetHingeAngle(hinge);
  if (!(angle > dJointGetHingeParam(hinge, dParamLoStop) && angle < dJointGetHingeParam(hinge, dParamHiStop))) {
    return RowCase::kTwoRows;
  }
  const double offset = rows.last_velocity - rows.last_rate;  // c1·λ1 while the motor was inside its limits
  if (std::abs(offset) >= c1 * rows.max_torque) return RowCase::kTwoRows;  // the motor was at its limit
  if (std::abs(rows.last_rate) < c2 * rows.friction) return RowCase::kBothFree;  // the brake held
  const double predicted_rate = rows.velocity - offset;  // the motor's load changes slowly
  if (std::abs(predicted_rate) < 2.0 * c2 * rows.friction) return RowCase::kTwoRows;  // may stop: unclear
  sign = predicted_rate > 0.0 ? 1.0 : -1.0;
  return RowCase::kBrakeSliding;
}

void OdeWorld::CombineRows(const CombinedJoint& joint) {
  const MotorRows& rows = motor_rows_[joint.joint];
  dJointID motor = motors_[joint.joint];
  dJointID hinge = joints_[joint.joint];
  switch (joint.row_case) {
    case RowCase::kTwoRows:
      return;
    case RowCase::kBrakeSliding:
      dJointSetHingeParam(hinge, dParamFMax, 0.0);
      dJointAddAMotorTorques(motor, -joint.sign * rows.friction, 0.0, 0.0);  // body1 +, body2 −, like the row
      return;
    case RowCase::kBothFree: {
      const double c1 = dJointGetAMotorParam(motor, dParamCFM);
      const double c2 = dJointGetHingeParam(hinge, dParamCFM);
      dJointSetHingeParam(hinge, dParamFMax, 0.0);
      dJointSetAMotorParam(motor, dParamVel, c2 * rows.velocity / (c1 + c2));
      dJointSetAMotorParam(motor, dParamCFM, c1 * c2 / (c1 + c2));
      dJointSetAMotorParam(motor, dParamFMax, dInfinity);
      return;
    }
  }
}

void OdeWorld::SeparateRows(const CombinedJoint& joint) {
  if (joint.row_case == RowCase::kTwoRows) return;
  const MotorRows& rows = motor_rows_[joint.joint];
  dJointSetHingeParam(joints_[joint.joint], dParamFMax, rows.friction);
  if (joint.row_case == RowCase::kBothFree) {
    dJointID motor = motors_[joint.joint];
    dJointSetAMotorParam(motor, dParamVel, rows.velocity);
    dJointSetAMotorParam(motor, dParamCFM, rows.cfm);
    dJointSetAMotorParam(motor, dParamFMax, rows.max_torque);
  }
}

// Whether the rate after the step is one the predicted case allows; then the two-row conditions hold as well.
bool OdeWorld::RowCaseHeld(const CombinedJoint& joint) const {
  const MotorRows& rows = motor_rows_[joint.joint];
  const double u = RateAbout(joint.joint, joint.axis);
  const double c1 = dJointGetAMotorParam(motors_[joint.joint], dParamCFM);
  const double c2 = dJointGetHingeParam(joints_[joint.joint], dParamCFM);
  switch (joint.row_case) {
    case RowCase::kTwoRows:
      return true;
    case RowCase::kBrakeSliding:
      return joint.sign * u >= c2 * rows.friction;
    case RowCase::kBothFree:
      return std::abs(u) <= c2 * rows.friction && std::abs(rows.velocity - u) <= c1 * rows.max_torque;
  }
  return false;
}

// In kBothFree one row carried motor and brake together, and ODE's feedback holds their sum. The motor's share is
// λ1 = (v − u)/c1, as in the two-row step; report that (joint_motor_torque).
void OdeWorld::ReportMotorShare(const CombinedJoint& joint) {
  const MotorRows& rows = motor_rows_[joint.joint];
  const double torque =
      (rows.velocity - RateAbout(joint.joint, joint.axis)) / dJointGetAMotorParam(motors_[joint.joint], dParamCFM);
  const bool two_bodies = model_->joint_body2(joint.joint) >= 0;
  dJointFeedback& feedback = motor_feedback_[joint.joint];
  for (int k = 0; k < 3; ++k) {
    feedback.f1[k] = 0.0;
    feedback.f2[k] = 0.0;
    feedback.t1[k] = torque * joint.axis[k];
    feedback.t2[k] = two_bodies ? -torque * joint.axis[k] : 0.0;
  }
}

// (ω1 − ω2)·axis, the rate both rows constrain (body 2 may be the static world).
double OdeWorld::RateAbout(int joint, const dVector3 axis) const {
  const dReal* w1 = dBodyGetAngularVel(bodies_[model_->joint_body1(joint)]);
  double rate = axis[0] * w1[0] + axis[1] * w1[1] + axis[2] * w1[2];
  const int b2 = model_->joint_body2(joint);
  if (b2 >= 0 && bodies_[b2] != nullptr) {
    const dReal* w2 = dBodyGetAngularVel(bodies_[b2]);
    rate -= axis[0] * w2[0] + axis[1] * w2[1] + axis[2] * w2[2];
  }
  return rate;
}

void OdeWorld::SaveBodies() {
  const auto copy = [](const dReal* from, dReal* to, int n) { std::copy(from, from + n, to); };
  for (size_t b = 0; b < bodies_.size(); ++b) {
    dBodyID id = bodies_[b];
    if (id == nullptr) continue;
    SavedBody& saved = saved_bodies_[b];
    copy(dBodyGetPosition(id), saved.position, 3);
    copy(dBodyGetQuaternion(id), saved.orientation, 4);
    copy(dBodyGetLinearVel(id), saved.linear_velocity, 3);
    copy(dBodyGetAngularVel(id), saved.angular_velocity, 3);
    // What was added for this step (AddJointTorque, ...), before CombineRows adds the brake torques.
    copy(dBodyGetForce(id), saved.force, 3);
    copy(dBodyGetTorque(id), saved.torque, 3);
  }
}

// ODE renormalises a quaternion it is given, so a repeated step may start a rounding error away from the first.
void OdeWorld::RestoreBodies() {
  for (size_t b = 0; b < bodies_.size(); ++b) {
    dBodyID id = bodies_[b];
    if (id == nullptr) continue;
    const SavedBody& saved = saved_bodies_[b];
    dBodySetPosition(id, saved.position[0], saved.position[1], saved.position[2]);
    dBodySetQuaternion(id, saved.orientation);
    dBodySetLinearVel(id, saved.linear_velocity[0], saved.linear_velocity[1], saved.linear_velocity[2]);
    dBodySetAngularVel(id, saved.angular_velocity[0], saved.angular_velocity[1], saved.angular_velocity[2]);
    dBodySetForce(id, saved.force[0], saved.force[1], saved.force[2]);
    dBodySetTorque(id, saved.torque[0], saved.torque[1], saved.torque[2]);
  }
}

StepStatus OdeWorld::CheckStability(const PhysicsParameters& p) const {
  const double max_linear2 = p.max_linear_speed * p.max_linear_speed;
  const double max_angular2 = p.max_angular_speed * p.max_angular_speed;
  for (dBodyID body : bodies_) {
    if (body == nullptr) continue;
    const dReal* x = dBodyGetPosition(body);
    const dReal* q = dBodyGetQuaternion(body);
    const dReal* v = dBodyGetLinearVel(body);
    const dReal* w = dBodyGetAngularVel(body);
    // One NaN or infinity anywhere makes the sum non-finite.
    const double sum = x[0] + x[1] + x[2] + q[0] + q[1] + q[2] + q[3] + v[0] + v[1] + v[2] + w[0] + w[1] + w[2];
    if (!std::isfinite(sum)) return StepStatus::kUnstable;
    if (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > max_linear2) return StepStatus::kUnstable;
    if (w[0] * w[0] + w[1] * w[1] + w[2] * w[2] > max_angular2) return StepStatus::kUnstable;
  }
  return StepStatus::kOk;
}

BodyState OdeWorld::body_state(int body) const {
  ORCS_DEMAND(body >= 0 && body < model_->body_count());
  BodyState state;
  dBodyID id = bodies_[body];
  if (id == nullptr) {  // static: where the description put it, at rest
    state.position = model_->body(body).position;
    state.orientation = model_->body(body).orientation;
    return state;
  }
  const dReal* x = dBodyGetPosition(id);
  const dReal* q = dBodyGetQuaternion(id);
  const dReal* v = dBodyGetLinearVel(id);
  const dReal* w = dBodyGetAngularVel(id);
  state.position = {x[0], x[1], x[2]};
  state.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);  // (w, x, y, z), as ODE stores it
  state.linear_velocity = {v[0], v[1], v[2]};
  state.angular_velocity = {w[0], w[1], w[2]};
  return state;
}

void OdeWorld::SetBodyState(int body, const BodyState& state) {
  ORCS_DEMAND(body >= 0 && body < model_->body_count());
  dBodyID id = bodies_[body];
  ORCS_DEMAND_MSG(id != nullptr, "SetBodyState needs a dynamic body");
  if (id == nullptr) return;
  dBodySetPosition(id, state.position.x(), state.position.y(), state.position.z());
  dQuaternion q;
  ToOde(state.orientation, q);
  dBodySetQuaternion(id, q);
  dBodySetLinearVel(id, state.linear_velocity.x(), state.linear_velocity.y(), state.linear_velocity.z());
  dBodySetAngularVel(id, state.angular_velocity.x(), state.angular_velocity.y(), state.angular_velocity.z());
}

double OdeWorld::joint_angle(int joint) const {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  return IsHinge(joint) ? dJointGetHingeAngle(joints_[joint]) : 0.0;
}

double OdeWorld::joint_rate(int joint) const {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  return IsHinge(joint) ? dJointGetHingeAngleRate(joints_[joint]) : 0.0;
}

double OdeWorld::joint_motor_torque(int joint) const {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  dJointID motor = motors_[joint];
  if (motor == nullptr) return 0.0;
  dVector3 axis;
  dJointGetAMotorAxis(motor, 0, axis);
  const dJointFeedback& feedback = motor_feedback_[joint];
  return feedback.t1[0] * axis[0] + feedback.t1[1] * axis[1] + feedback.t1[2] * axis[2];
}

void OdeWorld::SetJointMotor(int joint, double velocity, double max_torque) {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  dJointID motor = motors_[joint];
  ORCS_DEMAND_MSG(motor != nullptr, "SetJointMotor needs a motorised hinge");
  if (motor == nullptr) return;
  dJointSetAMotorParam(motor, dParamVel, velocity);
  dJointSetAMotorParam(motor, dParamFMax, std::max(0.0, max_torque));  // a negative limit means none
  motor_rows_[joint].velocity = velocity;
  motor_rows_[joint].max_torque = std::max(0.0, max_torque);
}

void OdeWorld::SetJointFriction(int joint, double max_torque) {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  ORCS_DEMAND_MSG(IsHinge(joint), "SetJointFriction needs a hinge");
  if (!IsHinge(joint)) return;
  dJointSetHingeParam(joints_[joint], dParamFMax, std::max(0.0, max_torque));
  motor_rows_[joint].friction = std::max(0.0, max_torque);
}

void OdeWorld::AddJointTorque(int joint, double torque) {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  ORCS_DEMAND_MSG(IsHinge(joint), "AddJointTorque needs a hinge");
  if (!IsHinge(joint)) return;
  dJointAddHingeTorque(joints_[joint], torque);  // ODE clears body torques after each step
}

void OdeWorld::SetJointMotorCompliance(int joint, double compliance) {
  ORCS_DEMAND(joint >= 0 && joint < model_->joint_count());
  dJointID motor = motors_[joint];
  ORCS_DEMAND_MSG(motor != nullptr, "SetJointMotorCompliance needs a motorised hinge");
  if (motor == nullptr) return;
  const double cfm = compliance > 0.0 ? compliance : kMotorCfm;
  dJointSetAMotorParam(motor, dParamCFM, cfm);
  motor_rows_[joint].cfm = cfm;
}

void OdeWorld::AddBodyInertia(int body, const Eigen::Vector3d& axis_in_body, double inertia) {
  ORCS_DEMAND(body >= 0 && body < model_->body_count());
  dBodyID id = bodies_[body];
  ORCS_DEMAND_MSG(id != nullptr, "AddBodyInertia needs a dynamic body");
  if (id == nullptr || !(inertia > 0.0)) return;
  const Eigen::Vector3d a = axis_in_body.normalized();
  dMass mass;
  dBodyGetMass(id, &mass);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) mass.I[4 * r + c] += inertia * a[r] * a[c];  // dMatrix3 rows are 4 wide
  }
  dBodySetMass(id, &mass);
}

}  // namespace

std::unique_ptr<PhysicsWorld> MakeOdeWorld(std::shared_ptr<const PhysicsModel> model) {
  if (model == nullptr) throw std::invalid_argument("MakeOdeWorld: model is null");
  return std::make_unique<OdeWorld>(std::move(model));
}

}  // namespace orcs::physics
