// Names of the two symbols every plugin exports (see plugin_api.hpp).
#pragma once
#define SCREE_PLUGIN_ENTRY_SYMBOL "scree_register_v1"
#define SCREE_PLUGIN_ABI_SYMBOL "scree_plugin_abi_v1"
