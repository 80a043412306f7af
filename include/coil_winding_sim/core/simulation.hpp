// One simulation run: a validated scene, its wire model and its integrator,
// with the run's statistics. The ROS node and wire_sim are thin users of it.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"
#include "coil_winding_sim/core/wire_model.hpp"

namespace cws {

class Simulation {
 public:
  // Validates the scene (throws SceneError) and builds the model.
  explicit Simulation(const Scene& scene);

  // One accepted step, not past t_limit [s]. Throws IntegrationError.
  void step(double t_limit);
  // Steps until the scene's end time; `progress` is called about every
  // output.progress_interval_s of wall time. Accumulates wall time.
  void run(const std::function<void(const Simulation&)>& progress = {});

  double time() const { return t_; }           // simulated time [s]
  double endTime() const { return t_end_; }    // [s]
  double wallTime() const { return wall_s_; }  // wall time spent in run() [s]
  double realTimeFactor() const { return wall_s_ > 0.0 ? t_ / wall_s_ : 0.0; }
  const Scene& scene() const { return scene_; }
  const WireModel& model() const { return *model_; }
  WireModel& model() { return *model_; }
  const TimeStepper& stepper() const { return *stepper_; }
  const Eigen::VectorXd& state() const { return y_; }
  EnergyReport energy() const { return model_->energy(y_); }
  // Largest values over all accepted steps.
  double maxConstraintResidual() const { return max_residual_; }
  double maxAxialForce() const { return max_axial_force_; }  // [N]
  // Deepest contact penetration over all accepted steps [m] (0 without contact).
  double maxPenetration() const { return max_penetration_; }
  // Core revolutions turned so far (0 without a core).
  double coreTurns() const;

 private:
  void afterStep();

  Scene scene_;
  std::unique_ptr<WireModel> model_;
  std::unique_ptr<TimeStepper> stepper_;
  Eigen::VectorXd y_;
  double t_ = 0.0;
  double t_end_ = 0.0;
  double wall_s_ = 0.0;
  double max_residual_ = 0.0;
  double max_axial_force_ = 0.0;
  double max_penetration_ = 0.0;
};

}  // namespace cws
