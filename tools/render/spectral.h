// Spectral transport helpers: CIE 1931 colour matching (the multi-lobe Gaussian fit of Wyman,
// Sloan and Shirley, JCGT 2013), XYZ to linear sRGB, RGB reflectance and emission as smooth
// spectra, and the index of refraction of a dispersive glTF material at a wavelength.
#pragma once

#include "render_math.h"

namespace obvh::render {

constexpr float kShortestWavelength = 400.f, kLongestWavelength = 700.f;  // nm

Vec3 cieXyz(float wavelengthNm);
Vec3 xyzToLinearSrgb(Vec3 xyz);

// The value at the wavelength of a smooth spectrum whose blue, green and red bands carry rgb's
// components; the bands sum to one everywhere, so white stays white and grey stays grey.
float rgbSpectrumAt(Vec3 rgb, float wavelengthNm);

// Linear sRGB contribution of a path that carried `radiance` at `wavelengthNm`, the wavelength
// drawn uniformly from [400, 700] nm; a flat spectrum of radiance 1 averages to rgb (1, 1, 1).
Vec3 spectralSampleToRgb(float radiance, float wavelengthNm);

// KHR_materials_dispersion: Abbe number V = 20 / dispersion, n(lambda) = n_d + (n_d - 1) / V *
// (523655 / lambda^2 - 1.5168), lambda in nm (a Cauchy fit through n_d at the sodium d line).
float iorAtWavelength(float ior, float dispersion, float wavelengthNm);

}  // namespace obvh::render
