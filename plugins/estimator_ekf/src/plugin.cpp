// estimator_ekf: registration of the plugin class (estimator_ekf_plugin.hpp).
#include "estimator_ekf_plugin.hpp"

using tern::ekf::plugin::EstimatorEkf;

TERN_PLUGIN(EstimatorEkf, "estimator_ekf", tern::PluginKind::estimator,
            "full-state multiplicative EKF: GNSS, baro, pitot, magnetometer, zero-sideslip; wind and biases");
