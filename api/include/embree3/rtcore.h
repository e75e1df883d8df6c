// obvh: umbrella header, source compatible with <embree3/rtcore.h> of Embree 3.13.5.
#pragma once

#include "rtcore_config.h"
#include "rtcore_common.h"
#include "rtcore_device.h"
#include "rtcore_buffer.h"
#include "rtcore_ray.h"
#include "rtcore_geometry.h"
#include "rtcore_scene.h"
#include "rtcore_builder.h"
#include "rtcore_quaternion.h"
