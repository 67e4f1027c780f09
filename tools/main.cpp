// The entry point of geovor (GEOVOR_TOOL_HAS_GDAL 0: linked without GDAL, hands GDAL jobs on)
// and of geovor-gdal (1: the same tool with GDAL linked).
namespace geovor::tools {
int run_geovor(int argc, char** argv, bool has_gdal);  // commands.hpp (CLI11's header is slow to compile)
}  // namespace geovor::tools

int main(int argc, char** argv) { return geovor::tools::run_geovor(argc, argv, GEOVOR_TOOL_HAS_GDAL != 0); }
