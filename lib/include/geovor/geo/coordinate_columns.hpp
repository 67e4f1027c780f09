/// \file coordinate_columns.hpp
/// \brief Which columns of a header hold the coordinates, found the way users name them, and
/// the header's own problems (a name twice, a column without a name).
///
/// A column name is read as words: what is in parentheses, brackets or braces is dropped
/// ("Latitude (deg)"), camelCase is split ("decimalLatitude"), letters are folded to lower case
/// and every other character separates words ("stop_lat", "Latitude [°]", "LAT-DD"). Words that
/// only say the unit or datum are dropped: deg, degs, degree, degrees, dd, decimal, dec, wgs,
/// wgs84, 84, 1984, wgs1984, epsg, 4326, m, metres, meters, ft, feet. What is left is ranked:
/// 1. the coordinate alone: lat, latitude / lon, lng, long, longitude (lat, Latitude,
///    latitude_deg of OurAirports, decimalLatitude of GBIF, LAT of NOAA ISD, "Latitude (WGS84)");
/// 2. the coordinate after other words: stop_lat (GTFS), pickup_latitude, verbatimLatitude
///    (lat, latitude / lon, lng, longitude; never "long": NAME_LONG is a name);
/// 3. y / x, alone or with point or coord: Y, POINT_Y (ArcGIS), ycoord, y_coord (QGIS);
///    with a projected source (--s-srs) these and northing / easting (also north / east) rank 1.
/// The best rank present wins; two or more columns sharing it are ambiguous (NYC taxi trips'
/// pickup_latitude and dropoff_latitude; lat and Latitude) and refused with the candidates named.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace geovor {

/// Which coordinate a column may hold.
enum class Axis { Latitude, Longitude };

/// How well `name` says `axis`: 1 best, 3 worst (the list above), 0 not at all. `projected`:
/// the source is in a projected CRS, whose x/y and easting/northing rank 1.
int coordinate_name_rank(std::string_view name, Axis axis, bool projected = false);

/// The column of `columns` with the best rank for `axis`; -1 when none has a rank.
/// \throw Error(ErrorCode::BadData) when several columns share the best rank: the message names
///   `source`, the axis and every candidate, and says which option picks one
///   (--<option_prefix>lat-field: "" for sites, "query-" for nearest's queries).
int detect_coordinate_column(const std::vector<std::string>& columns, Axis axis, bool projected,
                             const std::string& source, std::string_view option_prefix = "");

/// Refuses a header whose names cannot tell its columns apart: a name that repeats an earlier one
/// (trimmed, case-insensitive, as columns are looked up and as GIS formats compare field names),
/// or an empty name other than in the last columns. Returns how many columns at the end have an
/// empty name (a trailing delimiter written by a spreadsheet); the reader accepts those only
/// while every row leaves them empty.
/// \throw Error(ErrorCode::BadData) naming `source`, the column's number and its name.
std::size_t check_header_names(const std::vector<std::string>& columns, const std::string& source);

}  // namespace geovor
