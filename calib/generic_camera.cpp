// SPDX-License-Identifier: MIT
/// @brief GenericCamera: creation by model name with parameter checks.
#include "calib/generic_camera.h"

#include <sstream>

namespace telesphere::calib {
namespace {

template <typename Model>
std::optional<GenericCamera> createModel(const Eigen::VectorXd& params, std::string* out_error) {
  if (params.size() != Model::kNumParams) {
    if (out_error) {
      std::ostringstream os;
      os << "model \"" << Model::kName << "\" takes " << Model::kNumParams << " parameters [";
      for (std::size_t i = 0; i < Model::kParamNames.size(); ++i)
        os << (i ? ", " : "") << Model::kParamNames[i];
      os << "], got " << params.size();
      *out_error = os.str();
    }
    return std::nullopt;
  }
  const Eigen::Matrix<double, Model::kNumParams, 1> p = params;
  if (auto error = Model::checkParams(p)) {
    if (out_error) *out_error = *error;
    return std::nullopt;
  }
  // Built in place: moving a temporary GenericCamera into the optional trips a GCC 12
  // -Wmaybe-uninitialized false positive on the variant.
  return std::optional<GenericCamera>(std::in_place, Model(p));
}

template <typename Model>
std::vector<std::string_view> namesOf() {
  return {Model::kParamNames.begin(), Model::kParamNames.end()};
}

}  // namespace

std::vector<std::string_view> GenericCamera::modelNames() {
  return {DoubleSphereCamera<double>::kName, ExtendedUnifiedCamera<double>::kName,
          KannalaBrandtCamera<double>::kName, PinholeRadtanCamera<double>::kName};
}

std::vector<std::string_view> GenericCamera::paramNames(std::string_view model) {
  if (model == DoubleSphereCamera<double>::kName) return namesOf<DoubleSphereCamera<double>>();
  if (model == ExtendedUnifiedCamera<double>::kName) return namesOf<ExtendedUnifiedCamera<double>>();
  if (model == KannalaBrandtCamera<double>::kName) return namesOf<KannalaBrandtCamera<double>>();
  if (model == PinholeRadtanCamera<double>::kName) return namesOf<PinholeRadtanCamera<double>>();
  return {};
}

std::optional<GenericCamera> GenericCamera::create(std::string_view model,
                                                   const Eigen::VectorXd& params,
                                                   std::string* out_error) {
  if (model == DoubleSphereCamera<double>::kName)
    return createModel<DoubleSphereCamera<double>>(params, out_error);
  if (model == ExtendedUnifiedCamera<double>::kName)
    return createModel<ExtendedUnifiedCamera<double>>(params, out_error);
  if (model == KannalaBrandtCamera<double>::kName)
    return createModel<KannalaBrandtCamera<double>>(params, out_error);
  if (model == PinholeRadtanCamera<double>::kName)
    return createModel<PinholeRadtanCamera<double>>(params, out_error);
  if (out_error) {
    std::ostringstream os;
    os << "unknown camera model \"" << model << "\" (known: ds, eucm, kb4, pinhole)";
    *out_error = os.str();
  }
  return std::nullopt;
}

std::string_view GenericCamera::modelName() const {
  return visit([](const auto& m) { return std::decay_t<decltype(m)>::kName; });
}

Eigen::VectorXd GenericCamera::params() const {
  return visit([](const auto& m) { return Eigen::VectorXd(m.params()); });
}

double GenericCamera::maxAngle() const {
  return visit([](const auto& m) { return m.maxAngle(); });
}

bool GenericCamera::project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& out_px) const {
  return visit([&](const auto& m) { return m.project(p_cam, out_px); });
}

bool GenericCamera::unproject(const Eigen::Vector2d& px, Eigen::Vector3d& out_d_cam) const {
  return visit([&](const auto& m) { return m.unproject(px, out_d_cam); });
}

}  // namespace telesphere::calib
