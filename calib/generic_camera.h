// SPDX-License-Identifier: MIT
/// @brief One of the camera models chosen at run time (from a calibration file): a variant over
///        DoubleSphereCamera, ExtendedUnifiedCamera, KannalaBrandtCamera and PinholeRadtanCamera,
///        in double precision. Hot loops should visit() once and run the concrete model.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "calib/double_sphere_camera.h"
#include "calib/extended_unified_camera.h"
#include "calib/kannala_brandt_camera.h"
#include "calib/pinhole_radtan_camera.h"

namespace telesphere::calib {

class GenericCamera {
 public:
  using Variant = std::variant<DoubleSphereCamera<double>, ExtendedUnifiedCamera<double>,
                               KannalaBrandtCamera<double>, PinholeRadtanCamera<double>>;

  template <typename Model>
  explicit GenericCamera(const Model& model) : model_(model) {}

  /// The model names we know, in the order of Variant: "ds", "eucm", "kb4", "pinhole".
  static std::vector<std::string_view> modelNames();

  /// Parameter names of a model in kalibr/Basalt order (empty for an unknown model).
  static std::vector<std::string_view> paramNames(std::string_view model);

  /// A camera of the named model; on an unknown model, a wrong parameter count or parameters
  /// outside the model's domain, nothing, with the reason (naming the parameter) in out_error.
  static std::optional<GenericCamera> create(std::string_view model, const Eigen::VectorXd& params,
                                             std::string* out_error = nullptr);

  std::string_view modelName() const;
  Eigen::VectorXd params() const;
  double maxAngle() const;

  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& out_px) const;
  bool unproject(const Eigen::Vector2d& px, Eigen::Vector3d& out_d_cam) const;

  template <typename Visitor>
  decltype(auto) visit(Visitor&& visitor) const {
    return std::visit(std::forward<Visitor>(visitor), model_);
  }

 private:
  Variant model_;
};

}  // namespace telesphere::calib
