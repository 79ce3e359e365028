// Test plugins with a deliberately wrong handshake, as a plugin built against another SDK would
// have. The factory aborts: the host must refuse these before calling any plugin code.
#include <cstdlib>

#include "tern/plugin.hpp"

namespace {
tern::Plugin* factory() { std::abort(); }
#define FP_(T) {T::type_name.data(), ::tern::reflect::fingerprint<T>()},
#if defined(TERN_BAD_FINGERPRINT)
// tern/Imu as an older SDK laid it out (no temperature field): a different fingerprint
constexpr tern_message_fingerprint fps[] = {{"tern/Imu", 0x0123456789abcdefull}, TERN_STANDARD_MESSAGES(FP_)};
#else
constexpr tern_message_fingerprint fps[] = {TERN_STANDARD_MESSAGES(FP_)};
#endif
}  // namespace

#if defined(TERN_BAD_API)
#define API_ 999
#define NAME_ "test_bad_api"
#else
#define API_ ::tern::kSdkApiVersion
#endif
#if defined(TERN_BAD_ABI)
#define ABI_ "libstdc++9;cxx11abi=0;eigen=3.3.7;eigen_align=32"
#define NAME_ "test_bad_abi"
#else
#define ABI_ TERN_ABI_TAG
#endif
#if defined(TERN_BAD_FINGERPRINT)
#define NAME_ "test_bad_fingerprint"
#endif

extern "C" BOOST_SYMBOL_EXPORT const tern_plugin_handshake TERN_HANDSHAKE_SYMBOL;
extern "C" BOOST_SYMBOL_EXPORT const tern_plugin_handshake TERN_HANDSHAKE_SYMBOL = {
    TERN_HANDSHAKE_MAGIC, API_, ABI_, NAME_, "generic", "deliberately mismatched", sizeof(fps) / sizeof(fps[0]), fps};
BOOST_DLL_ALIAS(factory, tern_create_plugin)
