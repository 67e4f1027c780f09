/// \file map_page.hpp
/// \brief /map of `geovor serve`: a Leaflet page (service/map/map.html) over the countries
/// (service/map/countries.geojson: Natural Earth 1:110m, public domain, as shipped with Debian's
/// python3-geopandas, names only, 2 decimals), both compiled into the program; Leaflet itself is
/// Debian's libjs-leaflet, served from where Debian installs it.
#pragma once

#include <string_view>

namespace geovor::service {

/// Where Debian's libjs-leaflet installs leaflet.js and leaflet.css.
inline constexpr const char* kLeafletDir = "/usr/share/javascript/leaflet";

std::string_view map_page();
std::string_view countries_geojson();

}  // namespace geovor::service
