// obvh: transform given as scale/skew/shift, a rotation quaternion and a translation.
#pragma once

#include "rtcore_common.h"

struct RTC_ALIGN(16) RTCQuaternionDecomposition
{
  float scale_x, scale_y, scale_z;
  float skew_xy, skew_xz, skew_yz;
  float shift_x, shift_y, shift_z;
  float quaternion_r, quaternion_i, quaternion_j, quaternion_k;
  float translation_x, translation_y, translation_z;
};

RTC_FORCEINLINE void rtcQuaternionDecompositionSetQuaternion(struct RTCQuaternionDecomposition* qdecomp,
                                                             float r, float i, float j, float k)
{
  qdecomp->quaternion_r = r;
  qdecomp->quaternion_i = i;
  qdecomp->quaternion_j = j;
  qdecomp->quaternion_k = k;
}

RTC_FORCEINLINE void rtcQuaternionDecompositionSetScale(struct RTCQuaternionDecomposition* qdecomp,
                                                        float scale_x, float scale_y, float scale_z)
{
  qdecomp->scale_x = scale_x;
  qdecomp->scale_y = scale_y;
  qdecomp->scale_z = scale_z;
}

RTC_FORCEINLINE void rtcQuaternionDecompositionSetSkew(struct RTCQuaternionDecomposition* qdecomp,
                                                       float skew_xy, float skew_xz, float skew_yz)
{
  qdecomp->skew_xy = skew_xy;
  qdecomp->skew_xz = skew_xz;
  qdecomp->skew_yz = skew_yz;
}

RTC_FORCEINLINE void rtcQuaternionDecompositionSetShift(struct RTCQuaternionDecomposition* qdecomp,
                                                        float shift_x, float shift_y, float shift_z)
{
  qdecomp->shift_x = shift_x;
  qdecomp->shift_y = shift_y;
  qdecomp->shift_z = shift_z;
}

RTC_FORCEINLINE void rtcQuaternionDecompositionSetTranslation(struct RTCQuaternionDecomposition* qdecomp,
                                                              float translation_x, float translation_y,
                                                              float translation_z)
{
  qdecomp->translation_x = translation_x;
  qdecomp->translation_y = translation_y;
  qdecomp->translation_z = translation_z;
}

// Identity: unit scale, no skew or shift, the unit quaternion, no translation.
RTC_FORCEINLINE void rtcInitQuaternionDecomposition(struct RTCQuaternionDecomposition* qdecomp)
{
  rtcQuaternionDecompositionSetScale(qdecomp, 1.f, 1.f, 1.f);
  rtcQuaternionDecompositionSetSkew(qdecomp, 0.f, 0.f, 0.f);
  rtcQuaternionDecompositionSetShift(qdecomp, 0.f, 0.f, 0.f);
  rtcQuaternionDecompositionSetQuaternion(qdecomp, 1.f, 0.f, 0.f, 0.f);
  rtcQuaternionDecompositionSetTranslation(qdecomp, 0.f, 0.f, 0.f);
}
