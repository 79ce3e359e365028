// A shared object that is not a tern plugin (no handshake), named like one.
extern "C" __attribute__((visibility("default"))) int tern_test_not_a_plugin_answer() { return 42; }
