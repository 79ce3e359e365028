// The fcu_serial plugin's registration (the class is in fcu_serial_plugin.hpp).
#include "fcu_serial_plugin.hpp"

TERN_PLUGIN(tern::fcu_serial::FcuSerial, "fcu_serial", tern::PluginKind::io,
            "flies through a ROSflight flight-control unit over MAVLink (serial port or UDP), or through tern-fcu-emulator");
