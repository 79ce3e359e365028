// core/apps/dds/include/external_link_dds.hpp: the Fast DDS side of `plugin: external` instances
// (core/host/runners/external_plugin.hpp). No Fast DDS inside: include it in core/apps freely.
#pragma once

namespace tern::core {

/// Registers the factory that gives external instances their DDS endpoints
/// (set_external_link_factory): one participant per instance, on the mission config's
/// `dds.domain` and network settings (`dds.interfaces`, `peers`, `multicast`; `dds.enabled` need
/// not be set); writers and readers with rclcpp's default QoS (reliable, volatile, keep last 10),
/// which every ROS 2 node's default publishers and subscriptions match.
void register_dds_external_links();

}  // namespace tern::core
