// tern/export.hpp: symbol visibility of the SDK library (libtern_sdk.so).
#pragma once

#define TERN_API __attribute__((visibility("default")))
