#include "model/physics/mujoco/mujoco_world.h"

#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <list>
#include <map>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "base/demand.h"
#include "model/core/error.h"
#include "model/physics/material_table.h"
#include "model/physics/mujoco/mjcf_export.h"

namespace orcs::physics {
namespace {

// MuJoCo prints warnings itself unless told otherwise; the world turns them into a step status instead.
void IgnoreWarning(const char*) {}

void InstallHandlersOnce() {
  static std::once_flag once;
  std::call_once(once, [] { mju_user_warning = IgnoreWarning; });
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// MuJoCo's compiler error on one line, in orcs's terms. It reads
//   Error: error 'inertia must have positive eigenvalues' in inertia alternative
//   Object name = Dust, id = 1, line = 12, column = -1
// and becomes "'Dust': inertia must have positive eigenvalues (line 12 of the generated MJCF)": Dust is the
// orcs body or geom of that name.
std::string CompilerMessage(const std::string& error) {
  // The text between `open` and the next `close` after it, "" when absent.
  const auto between = [&error](const std::string& open, const std::string& close) {
    const size_t start = error.find(open);
    if (start == std::string::npos) return std::string();
    const size_t from = start + open.size();
    return error.substr(from, error.find(close, from) - from);
  };
  std::string reason = between("error '", "'");
  if (reason.empty()) reason = error;
  const std::string object = between("Object name = ", ",");
  const std::string line = between("line = ", ",");
  std::string message = (object.empty() ? "" : "'" + object + "': ") + reason;
  if (!line.empty()) message += " (line " + line + " of the generated MJCF)";
  std::replace(message.begin(), message.end(), '\n', ' ');
  return message;
}

ModelPtr CompileMjcf(const std::string& xml) {
  InstallHandlersOnce();
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* kFile = "orcs.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), kFile, static_cast<int>(xml.size())) != 0) {
    throw InputError("MuJoCo: cannot hold the generated model in memory");
  }
  std::memcpy(vfs->filedata[vfs->nfile - 1], xml.data(), xml.size());
  char error[1000] = "";
  ModelPtr model(mj_loadXML(kFile, vfs.get(), error, sizeof error));
  mj_deleteVFS(vfs.get());
  if (!model) throw InputError("MuJoCo cannot compile the world: " + CompilerMessage(error));
  return model;
}

// Compiled models by their MJCF text, shared read-only: a worker runs many jobs of one world, and compiling is
// most of what making a world costs. Bounded to the last few texts; a world copies its model, so a model
// dropped from the cache lives on in the worlds made from it.
std::shared_ptr<const mjModel> CompiledModel(const std::string& xml) {
  constexpr size_t kCachedModels = 4;
  static std::mutex mutex;
  static std::list<std::pair<std::string, std::shared_ptr<const mjModel>>> cache;  // most recent first
  const std::lock_guard<std::mutex> lock(mutex);
  const auto found =
      std::find_if(cache.begin(), cache.end(), [&](const auto& entry) { return entry.first == xml; });
  if (found != cache.end()) {
    cache.splice(cache.begin(), cache, found);
    return cache.front().second;
  }
  std::shared_ptr<const mjModel> model(CompileMjcf(xml).release(), ModelDeleter());
  cache.emplace_front(xml, model);
  if (cache.size() > kCachedModels) cache.pop_back();
  return model;
}

int Id(const mjModel* m, mjtObj type, const std::string& name) {
  const int id = mj_name2id(m, type, name.c_str());
  ORCS_DEMAND_MSG(id >= 0, "the generated MJCF names every body, joint and geom it is asked for");
  return id;
}

Eigen::Vector3d Vec(const mjtNum* v) { return {v[0], v[1], v[2]}; }

constexpr std::array<const char*, mjNWARNING> kWarningNames = {
    "(near) singular inertia matrix", "too many contacts in the contact list", "too many constraints",
    "too many visual geoms", "bad number in qpos", "bad number in qvel", "bad number in qacc", "bad number in ctrl"};

class MujocoWorld : public PhysicsWorld {
 public:
  explicit MujocoWorld(std::shared_ptr<const PhysicsModel> model)
      : model_(std::move(model)), pristine_(CompiledModel(ExportMjcf(*model_, {.exclusions = true}))) {
    m_.reset(mj_copyModel(nullptr, pristine_.get()));
    d_.reset(mj_makeData(m_.get()));
    MapIndices();
    material_of_body_.resize(model_->body_count());
    for (int b = 0; b < model_->body_count(); ++b) {
      const BodyDescription& body = model_->body(b);
      material_of_body_[b] = {body.static_friction, body.dynamic_friction, body.elasticity};
    }
    Reset();
  }

  void Reset() override {
    mj_copyModel(m_.get(), pristine_.get());
    mj_resetData(m_.get(), d_.get());
    target_.assign(m_->ntendon, 0.0);
    compliance_.assign(m_->ntendon, 0.0);
    torque_.assign(m_->ntendon, 0.0);
    motor_row_.assign(m_->ntendon, -1);
    steps_ = 0;
    applied_.assign(m_->nv, 0.0);
    pending_.clear();
    contacts_.clear();
    status_ = StepStatus::kOk;
    last_error_.clear();
    UpdateKinematics();
  }

  StepStatus Step(double dt, const PhysicsParameters& parameters) override {
    if (status_ != StepStatus::kOk) return status_;
    PoseBodies();
    parameters_ = &parameters;
    SetOptions(dt, parameters);
    std::copy(applied_.begin(), applied_.end(), d_->qfrc_applied);
    const std::array<int, mjNWARNING> warnings_before = WarningCounts();
    PositionStages();
    mj_sensorPos(m_.get(), d_.get());
    mj_energyPos(m_.get(), d_.get());
    mj_fwdVelocity(m_.get(), d_.get());
    ServoReferences();
    mj_sensorVel(m_.get(), d_.get());
    mj_energyVel(m_.get(), d_.get());
    mj_step2(m_.get(), d_.get());
    ReadMotorTorques();
    ++steps_;
    std::fill(applied_.begin(), applied_.end(), 0.0);
    std::fill(d_->qfrc_applied, d_->qfrc_applied + m_->nv, 0.0);
    UpdateKinematics();
    status_ = CheckWarnings(warnings_before);
    if (status_ == StepStatus::kOk) status_ = CheckStability(parameters);
    return status_;
  }

  const std::vector<Contact>& contacts() const override { return contacts_; }
  void SetReportExcludedContacts(bool report) override { report_excluded_ = report; }

  BodyState body_state(int body) const override {
    if (const auto found = pending_.find(body); found != pending_.end()) return found->second;
    BodyState state;
    if (mj_body_[body] < 0) {
      state.position = model_->body(body).position;
      state.orientation = model_->body(body).orientation.normalized();
      return state;
    }
    const int id = mj_body_[body];
    state.position = Vec(d_->xpos + 3 * id);
    const mjtNum* q = d_->xquat + 4 * id;
    state.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    mjtNum velocity[6];
    mj_objectVelocity(m_.get(), d_.get(), mjOBJ_BODY, id, velocity, 0);
    state.angular_velocity = Vec(velocity);
    state.linear_velocity = Vec(velocity + 3);
    return state;
  }

  // Poses are kept until the next step or joint reading and then applied root first (PoseBodies): a jointed
  // body's pose becomes its joint's angle, which needs its parent's new pose. Until then body_state reads them
  // back, so that a caller moving several bodies rigidly (a whole agent, the far side of a hinge) reads each
  // body where it was and sets it where it goes, as on an engine with independent bodies.
  void SetBodyState(int body, const BodyState& state) override {
    if (mj_body_[body] < 0) return;  // static: never moves
    pending_[body] = state;
  }

  double joint_angle(int joint) const override {
    PoseBodies();
    return hinge_qpos_[joint] < 0 ? 0.0 : d_->qpos[hinge_qpos_[joint]];
  }
  double joint_rate(int joint) const override {
    PoseBodies();
    return hinge_dof_[joint] < 0 ? 0.0 : d_->qvel[hinge_dof_[joint]];
  }
  double joint_motor_torque(int joint) const override {
    return motor_[joint] < 0 || steps_ == 0 ? 0.0 : torque_[motor_[joint]];
  }

  void SetJointMotor(int joint, double velocity, double max_torque) override {
    const int t = motor_[joint];
    if (t < 0) return;
    target_[t] = velocity;
    m_->tendon_frictionloss[t] = max_torque;
  }
  void SetJointFriction(int joint, double max_torque) override {
    if (hinge_dof_[joint] >= 0) m_->dof_frictionloss[hinge_dof_[joint]] = max_torque;
  }
  void AddJointTorque(int joint, double torque) override {
    if (hinge_dof_[joint] >= 0) applied_[hinge_dof_[joint]] += torque;
  }
  void SetJointMotorCompliance(int joint, double compliance) override {
    if (motor_[joint] >= 0) compliance_[motor_[joint]] = compliance;
  }
  void AddBodyInertia(int body, const Eigen::Vector3d& axis_in_body, double inertia) override;

  const std::string& last_error() const override { return last_error_; }
  const PhysicsModel& model() const override { return *model_; }

 private:
  void MapIndices();
  void SetOptions(double dt, const PhysicsParameters& parameters);
  void ServoReferences();
  void MakeCompliant(int row, double target, double compliance);
  void ReadMotorTorques();
  void PoseBodies() const;
  void PoseBody(int body, const BodyState& state) const;
  void PositionStages();
  void RewriteContacts();
  void CollideExcludedPairs();
  double ChooseFriction(const mjContact& contact, const ContactMaterial& material);
  Eigen::Vector3d PointVelocity(int body, const mjtNum* point) const;
  // Poses, centres of mass and velocities of the bodies for the state as it stands: what readings need after a
  // step, and what the next step's position stages would compute again (they skip it while it is current).
  void UpdateKinematics() const {
    mj_kinematics(m_.get(), d_.get());
    mj_comPos(m_.get(), d_.get());
    mj_comVel(m_.get(), d_.get());
    kinematics_current_ = true;
  }
  std::array<int, mjNWARNING> WarningCounts() const {
    std::array<int, mjNWARNING> counts{};
    for (int i = 0; i < mjNWARNING; ++i) counts[i] = d_->warning[i].number;
    return counts;
  }
  StepStatus CheckWarnings(const std::array<int, mjNWARNING>& before);
  StepStatus CheckStability(const PhysicsParameters& parameters);

  std::shared_ptr<const PhysicsModel> model_;
  std::shared_ptr<const mjModel> pristine_;   ///< as compiled (shared): Reset() restores m_ from it
  ModelPtr m_;                                ///< this world's model, with the run's motor and friction settings
  DataPtr d_;                                 ///< this world's state
  std::vector<int> mj_body_;                  ///< orcs body → MuJoCo body id, −1 for a static body
  std::vector<int> orcs_geom_;                ///< MuJoCo geom id → orcs geom
  std::vector<int> hinge_qpos_;               ///< orcs joint → qpos address of its hinge, −1 for fixed joints
  std::vector<int> hinge_dof_;                ///< orcs joint → dof address of its hinge, −1 for fixed joints
  std::vector<int> motor_;                    ///< orcs joint → its motor tendon, −1 for unmotorised joints
  std::vector<BodyFrictionParameters> material_of_body_;  ///< the fallback friction of unknown materials, per body
  std::vector<double> target_;                ///< per motor tendon: target joint rate, rad/s
  std::vector<double> compliance_;            ///< per motor tendon: rad/s per N·m (0 = stiff)
  std::vector<double> torque_;                ///< per motor tendon: torque its row applied in the last step, N·m
  std::vector<int> motor_row_;                ///< per motor tendon: its constraint row in this step, −1 for none
  long steps_ = 0;                            ///< steps since Reset (no motor torque before the first)
  std::vector<double> applied_;               ///< per dof: torques added for the next step (AddJointTorque)
  std::vector<Contact> contacts_;             ///< found in the last step
  /// MuJoCo geom pairs the compiled <exclude> list hides from mj_collision but the report tests; see
  /// CollideExcludedPairs
  std::vector<std::pair<int, int>> excluded_geom_pairs_;
  bool report_excluded_ = true;               ///< SetReportExcludedContacts
  /// SetBodyState's poses not yet applied, by orcs body; mutable: a const reading applies them first
  mutable std::map<int, BodyState> pending_;
  const PhysicsParameters* parameters_ = nullptr;  ///< the running step's parameters
  /// d_'s kinematics and centre-of-mass quantities match its qpos and m_ (UpdateKinematics since the last change)
  mutable bool kinematics_current_ = false;
  StepStatus status_ = StepStatus::kOk;
  std::string last_error_;
};

// A motor is its tendon's friction-loss row: MuJoCo makes it a bounded constraint towards zero velocity with the
// reference acceleration −B·v. Shifted to −B·(v − target), the same row drives the joint towards the motor's
// target with at most its torque limit: ODE's angular motor. Compliance c yields as ODE's does, u = target − c·τ,
// with τ the motor's torque in the last step. Runs after the velocity stages, which compute the references.
void MujocoWorld::ServoReferences() {
  std::fill(motor_row_.begin(), motor_row_.end(), -1);
  for (int i = 0; i < d_->nefc; ++i) {
    if (d_->efc_type[i] != mjCNSTR_FRICTION_TENDON) continue;
    const int t = d_->efc_id[i];
    motor_row_[t] = i;
    if (compliance_[t] > 0.0) {
      MakeCompliant(i, target_[t], compliance_[t]);
    } else {
      d_->efc_aref[i] += d_->efc_KBIP[4 * i + 1] * target_[t];
    }
  }
}

// Compliance c as the row's own softness, so the spring is implicit as ODE's CFM makes it. Inside its force
// bound a MuJoCo row solves J·qacc = aref − R·f. With aref = (target − J·v)/dt and R = c/dt, one Euler step ends
// at J·v' = target − c·f: the motor yields by this step's torque, not the last one's.
void MujocoWorld::MakeCompliant(int row, double target, double compliance) {
  const double dt = m_->opt.timestep;
  d_->efc_aref[row] = (target - d_->efc_vel[row]) / dt;
  d_->efc_R[row] = compliance / dt;
  d_->efc_D[row] = 1.0 / d_->efc_R[row];
}

// The force each motor's row applied in the step just taken (0 when its limit was 0: no row).
void MujocoWorld::ReadMotorTorques() {
  for (std::size_t t = 0; t < torque_.size(); ++t) {
    torque_[t] = motor_row_[t] < 0 ? 0.0 : d_->efc_force[motor_row_[t]];
  }
}

// Root first (MuJoCo numbers bodies parent before child), each after its parent is in place: a free body takes
// its pose and velocities, a hinged one the angle and rate that put it closest (its rotation about the axis
// relative to its parent), a welded one follows its parent.
void MujocoWorld::PoseBodies() const {
  if (pending_.empty()) return;
  std::vector<std::pair<int, int>> order;  // MuJoCo id, orcs body
  for (const auto& [body, state] : pending_) order.emplace_back(mj_body_[body], body);
  std::sort(order.begin(), order.end());
  for (const auto& [id, body] : order) PoseBody(body, pending_.at(body));
  pending_.clear();
}

void MujocoWorld::PoseBody(int body, const BodyState& state) const {
  const int id = mj_body_[body];
  const int joint = m_->body_jntnum[id] > 0 ? m_->body_jntadr[id] : -1;
  mjData* d = d_.get();
  if (joint >= 0 && m_->jnt_type[joint] == mjJNT_FREE) {
    mjtNum* qpos = d->qpos + m_->jnt_qposadr[joint];
    mjtNum* qvel = d->qvel + m_->jnt_dofadr[joint];
    const Eigen::Quaterniond q = state.orientation.normalized();
    const Eigen::Vector3d local_spin = q.conjugate() * state.angular_velocity;  // a free joint's ω is local
    for (int i = 0; i < 3; ++i) {
      qpos[i] = state.position[i];
      qvel[i] = state.linear_velocity[i];
      qvel[3 + i] = local_spin[i];
    }
    qpos[3] = q.w(), qpos[4] = q.x(), qpos[5] = q.y(), qpos[6] = q.z();
  } else if (joint >= 0 && m_->jnt_type[joint] == mjJNT_HINGE) {
    // The child's orientation with its hinge at 0 (parent × the body's fixed offset) against the wanted one.
    const int parent = m_->body_parentid[id];
    const mjtNum* pq = d->xquat + 4 * parent;
    const mjtNum* bq = m_->body_quat + 4 * id;
    const Eigen::Quaterniond at_zero = Eigen::Quaterniond(pq[0], pq[1], pq[2], pq[3]) *
                                       Eigen::Quaterniond(bq[0], bq[1], bq[2], bq[3]);
    const Eigen::Quaterniond turn = at_zero.conjugate() * state.orientation.normalized();  // in the child frame
    const Eigen::Vector3d axis = Vec(m_->jnt_axis + 3 * joint).normalized();
    const Eigen::Vector3d vector_part(turn.x(), turn.y(), turn.z());
    d->qpos[m_->jnt_qposadr[joint]] = 2.0 * std::atan2(vector_part.dot(axis), turn.w());
    mjtNum parent_velocity[6];
    mj_objectVelocity(m_.get(), d, mjOBJ_BODY, parent, parent_velocity, 0);
    const Eigen::Vector3d world_axis = state.orientation.normalized() * axis;
    d->qvel[m_->jnt_dofadr[joint]] = (state.angular_velocity - Vec(parent_velocity)).dot(world_axis);
  }
  UpdateKinematics();
}

void MujocoWorld::MapIndices() {
  const mjModel* m = m_.get();
  mj_body_.assign(model_->body_count(), -1);
  for (int b = 0; b < model_->body_count(); ++b) {
    if (model_->body(b).dynamic) mj_body_[b] = Id(m, mjOBJ_BODY, model_->body(b).name);
  }
  orcs_geom_.assign(m->ngeom, -1);
  for (int g = 0; g < model_->geom_count(); ++g) orcs_geom_[Id(m, mjOBJ_GEOM, MjcfGeomName(*model_, g))] = g;
  // The pairs mj_collision would test but for the exclusion list: MuJoCo's own filters (contact bits, bodies
  // welded together) still apply.
  excluded_geom_pairs_.clear();
  for (int g1 = 0; g1 < m->ngeom; ++g1) {
    for (int g2 = g1 + 1; g2 < m->ngeom; ++g2) {
      const int b1 = model_->geom(orcs_geom_[g1]).body;
      const int b2 = model_->geom(orcs_geom_[g2]).body;
      const bool bits = (m->geom_contype[g1] & m->geom_conaffinity[g2]) || (m->geom_contype[g2] & m->geom_conaffinity[g1]);
      const bool welded = m->body_weldid[m->geom_bodyid[g1]] == m->body_weldid[m->geom_bodyid[g2]];
      if (b1 != b2 && bits && !welded && model_->contact_excluded(b1, b2)) excluded_geom_pairs_.emplace_back(g1, g2);
    }
  }
  hinge_qpos_.assign(model_->joint_count(), -1);
  hinge_dof_.assign(model_->joint_count(), -1);
  motor_.assign(model_->joint_count(), -1);
  for (int j = 0; j < model_->joint_count(); ++j) {
    const JointDescription& joint = model_->joint(j);
    if (joint.type != JointType::kHinge) continue;
    const int id = Id(m, mjOBJ_JOINT, joint.name);
    hinge_qpos_[j] = m->jnt_qposadr[id];
    hinge_dof_[j] = m->jnt_dofadr[id];
    if (joint.motorised) motor_[j] = Id(m, mjOBJ_TENDON, MjcfMotorName(*model_, j));
  }
}

void MujocoWorld::SetOptions(double dt, const PhysicsParameters& parameters) {
  const MujocoSettings& settings = parameters.mujoco;
  mjOption& opt = m_->opt;
  opt.timestep = dt;
  for (int i = 0; i < 3; ++i) opt.gravity[i] = parameters.gravity[i];
  switch (settings.solver) {
    case MujocoSolver::kPGS: opt.solver = mjSOL_PGS; break;
    case MujocoSolver::kCG: opt.solver = mjSOL_CG; break;
    case MujocoSolver::kNewton: opt.solver = mjSOL_NEWTON; break;
  }
  opt.iterations = settings.iterations;
  opt.tolerance = settings.tolerance;
  opt.integrator = settings.implicit_integrator ? mjINT_IMPLICIT : mjINT_EULER;
  opt.cone = settings.elliptic_cone ? mjCONE_ELLIPTIC : mjCONE_PYRAMIDAL;
}

// mj_fwdPosition's stages, with the contacts rewritten between collision and constraint making.
void MujocoWorld::PositionStages() {
  mjModel* m = m_.get();
  mjData* d = d_.get();
  const int bad_before = d->warning[mjWARN_BADQPOS].number + d->warning[mjWARN_BADQVEL].number;
  mj_checkPos(m, d);
  mj_checkVel(m, d);
  const bool reset_by_check = d->warning[mjWARN_BADQPOS].number + d->warning[mjWARN_BADQVEL].number != bad_before;
  if (!kinematics_current_ || reset_by_check) {
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_comVel(m, d);  // the contacts' friction reads the bodies' velocities
  }
  kinematics_current_ = false;  // the step integrates next
  mj_camlight(m, d);
  mj_tendon(m, d);
  mj_crb(m, d);
  mj_factorM(m, d);
  mj_collision(m, d);
  RewriteContacts();
  if (report_excluded_) CollideExcludedPairs();
  mj_makeConstraint(m, d);
  mj_transmission(m, d);
}

void MujocoWorld::RewriteContacts() {
  const PhysicsParameters& p = *parameters_;
  contacts_.clear();
  for (int i = 0; i < d_->ncon; ++i) {
    mjContact& con = d_->contact[i];
    const int g1 = orcs_geom_[con.geom1];
    const int g2 = orcs_geom_[con.geom2];
    const GeomInfo& info1 = model_->geom(g1);
    const GeomInfo& info2 = model_->geom(g2);
    const double depth = -con.dist;
    if (std::abs(depth) < p.min_contact_depth) {
      con.exclude = 1;  // no constraint, not reported: as ODE drops it
      continue;
    }
    Contact& contact = contacts_.emplace_back();
    contact.geom1 = g1;
    contact.geom2 = g2;
    contact.body1 = info1.body;
    contact.body2 = info2.body;
    contact.position = Vec(con.pos);
    contact.normal = -Vec(con.frame);  // MuJoCo's normal points from geom1 to geom2; ours into geom1
    contact.depth = depth;
    ORCS_DEMAND_MSG(!model_->contact_excluded(info1.body, info2.body), "the compiled <exclude> list hides those pairs");
    const ContactMaterial material =
        MaterialTable::Lookup(info1.material, info2.material, material_of_body_[info1.body],
                              material_of_body_[info2.body], p.custom1, p.custom2);
    con.friction[0] = con.friction[1] = ChooseFriction(con, material);
    con.mu = con.friction[0];
    // A frictionless pair (the table has some) is a normal-only contact: a friction cone with μ = 0 has
    // zero-weight rows, whose regularisation is 0 and whose solve is NaN ("bad number in qacc").
    con.dim = con.mu < mjMINMU ? 1 : 3;
    con.solref[0] = p.mujoco.contact_time_constant;
    con.solref[1] = p.mujoco.contact_damping_ratio;
  }
}

// The exclusion list's pairs, which mj_collision skips (compiled as <exclude>), tested with MuJoCo's own
// narrowphase the way mj_collision tests a pair (lower geom type first, bounding spheres, then the pair's
// function) and reported as excluded contacts: the original's collision events for them. They never reach
// d_->contact, so they make no constraint.
void MujocoWorld::CollideExcludedPairs() {
  const mjModel* m = m_.get();
  const mjData* d = d_.get();
  std::array<mjContact, mjMAXCONPAIR> found;
  for (auto [g1, g2] : excluded_geom_pairs_) {
    if (m->geom_type[g1] > m->geom_type[g2]) std::swap(g1, g2);
    const mjfCollision collide = mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]];
    if (collide == nullptr) continue;
    const double margin = std::max(m->geom_margin[g1], m->geom_margin[g2]);
    const double reach = m->geom_rbound[g1] + m->geom_rbound[g2] + margin;
    const bool bounded = m->geom_rbound[g1] > 0 && m->geom_rbound[g2] > 0;  // 0: a plane, unbounded
    if (bounded && (Vec(d->geom_xpos + 3 * g1) - Vec(d->geom_xpos + 3 * g2)).norm() > reach) continue;
    const int count = collide(m, d, found.data(), g1, g2, margin);
    for (int i = 0; i < count; ++i) {
      const double depth = -found[i].dist;
      if (std::abs(depth) < parameters_->min_contact_depth) continue;
      Contact& contact = contacts_.emplace_back();
      contact.geom1 = orcs_geom_[g1];
      contact.geom2 = orcs_geom_[g2];
      contact.body1 = model_->geom(contact.geom1).body;
      contact.body2 = model_->geom(contact.geom2).body;
      contact.position = Vec(found[i].pos);
      contact.normal = -Vec(found[i].frame);
      contact.depth = depth;
      contact.excluded = true;
    }
  }
}

// Static coefficient while the surfaces do not slide at the contact point, else the scaled dynamic one (the
// ODE backend's rule, docs/model.md).
double MujocoWorld::ChooseFriction(const mjContact& con, const ContactMaterial& material) {
  const PhysicsParameters& p = *parameters_;
  const Eigen::Vector3d relative =
      PointVelocity(m_->geom_bodyid[con.geom1], con.pos) - PointVelocity(m_->geom_bodyid[con.geom2], con.pos);
  const Eigen::Vector3d normal = Vec(con.frame);
  const Eigen::Vector3d tangential = relative - relative.dot(normal) * normal;
  return tangential.squaredNorm() < p.static_friction_speed * p.static_friction_speed
             ? material.static_friction
             : material.dynamic_friction * p.friction_scaling;
}

// The world-frame velocity of `point` moving with MuJoCo body `body`: the body's spatial velocity (cvel, taken at
// its tree's centre of mass) moved to the point. What mj_jac·qvel gives, without the Jacobian.
Eigen::Vector3d MujocoWorld::PointVelocity(int body, const mjtNum* point) const {
  const mjtNum* velocity = d_->cvel + 6 * body;
  const Eigen::Vector3d angular = Vec(velocity);
  const Eigen::Vector3d arm = Vec(point) - Vec(d_->subtree_com + 3 * m_->body_rootid[body]);
  return Vec(velocity + 3) + angular.cross(arm);
}

StepStatus MujocoWorld::CheckWarnings(const std::array<int, mjNWARNING>& before) {
  for (int i = 0; i < mjNWARNING; ++i) {
    if (d_->warning[i].number == before[i]) continue;
    last_error_ = std::string("MuJoCo: ") + kWarningNames[i] + " (at " + std::to_string(d_->warning[i].lastinfo) + ")";
    return StepStatus::kEngineError;
  }
  return StepStatus::kOk;
}

StepStatus MujocoWorld::CheckStability(const PhysicsParameters& parameters) {
  for (int i = 0; i < m_->nq; ++i) {
    if (!std::isfinite(d_->qpos[i])) return StepStatus::kUnstable;
  }
  for (int b = 0; b < model_->body_count(); ++b) {
    if (mj_body_[b] < 0) continue;
    const BodyState state = body_state(b);
    if (!state.linear_velocity.allFinite() || !state.angular_velocity.allFinite() ||
        state.linear_velocity.norm() > parameters.max_linear_speed ||
        state.angular_velocity.norm() > parameters.max_angular_speed) {
      return StepStatus::kUnstable;
    }
  }
  return StepStatus::kOk;
}

// I' = I + inertia·a·aᵀ in the body frame, diagonalised again into MuJoCo's principal inertia and its frame.
void MujocoWorld::AddBodyInertia(int body, const Eigen::Vector3d& axis_in_body, double inertia) {
  const int id = mj_body_[body];
  if (id < 0) return;
  const mjtNum* q = m_->body_iquat + 4 * id;
  const Eigen::Matrix3d frame = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  const Eigen::Vector3d principal = Vec(m_->body_inertia + 3 * id);
  const Eigen::Vector3d a = axis_in_body.normalized();
  const Eigen::Matrix3d full = frame * principal.asDiagonal() * frame.transpose() + inertia * a * a.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(full);
  Eigen::Matrix3d axes = solver.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);  // a rotation, not a reflection
  const Eigen::Quaterniond turned(axes);
  for (int i = 0; i < 3; ++i) m_->body_inertia[3 * id + i] = solver.eigenvalues()[i];
  mjtNum* iq = m_->body_iquat + 4 * id;
  iq[0] = turned.w(), iq[1] = turned.x(), iq[2] = turned.y(), iq[3] = turned.z();
  // mj_setConst evaluates the model at qpos0 in d_: keep the running state around it.
  const std::vector<mjtNum> qpos(d_->qpos, d_->qpos + m_->nq), qvel(d_->qvel, d_->qvel + m_->nv);
  mj_setConst(m_.get(), d_.get());
  std::copy(qpos.begin(), qpos.end(), d_->qpos);
  std::copy(qvel.begin(), qvel.end(), d_->qvel);
  UpdateKinematics();  // the bodies' inertia changed
}

}  // namespace

std::unique_ptr<PhysicsWorld> MakeMujocoWorld(std::shared_ptr<const PhysicsModel> model) {
  return std::make_unique<MujocoWorld>(std::move(model));
}

}  // namespace orcs::physics
