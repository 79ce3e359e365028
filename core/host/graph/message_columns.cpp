#include "graph/message_columns.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace tern::core {

const reflect::Column* find_column(const std::vector<reflect::Column>& columns, const std::string& name) {
  for (const auto& c : columns)
    if (c.name == name) return &c;
  return nullptr;
}

std::string column_problem(const reflect::Column& c, double v) {
  if (!std::isfinite(v)) return fmt::format("field '{}': {} is not a finite number", c.name, v);
  if (c.kind == reflect::Scalar::boolean)
    return v == 0.0 || v == 1.0 ? "" : fmt::format("field '{}' is a bool: {} is not 0 or 1", c.name, v);
  return detail::with_scalar(c.kind, [&](auto zero) -> std::string {
    using T = decltype(zero);
    if constexpr (std::is_integral_v<T>) {
      if (v != std::trunc(v) || v < static_cast<double>(std::numeric_limits<T>::min()) ||
          v > static_cast<double>(std::numeric_limits<T>::max()))
        return fmt::format("field '{}' is an integer of {} bytes: {} does not fit", c.name, sizeof(T), v);
    }
    return "";
  });
}

std::string column_names(const std::vector<reflect::Column>& columns) {
  std::string out;
  for (const auto& c : columns) out += (out.empty() ? "" : ", ") + c.name;
  return out;
}

}  // namespace tern::core
