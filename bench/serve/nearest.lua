-- wrk script of bench/serve/run.sh: GET /nearest?lat=..&lon=.. at a random point of a fixed list.
-- Usage: wrk ... -s nearest.lua URL -- POINTS.csv [SEED]
-- POINTS.csv: the header lat,lon then one point a line (make_points.py). The requests are built
-- once per thread in init(); each thread draws from its own seeded sequence.

local counter = 0
function setup(thread)
  counter = counter + 1
  thread:set("thread_no", counter)
end

local requests = {}

function init(args)
  local path = args[1]
  local seed = tonumber(args[2] or "34")
  local f = assert(io.open(path, "r"), "cannot open " .. tostring(path))
  local first = true
  for line in f:lines() do
    if first then
      first = false
    else
      local lat, lon = line:match("^([^,]+),([^,]+)$")
      if lat then
        requests[#requests + 1] = wrk.format("GET", "/nearest?lat=" .. lat .. "&lon=" .. lon)
      end
    end
  end
  f:close()
  assert(#requests > 0, "no points in " .. path)
  math.randomseed(seed * 1000 + (thread_no or 0))
end

function request()
  return requests[math.random(#requests)]
end
-- No response() callback: it would make wrk parse every answer; wrk itself counts the
-- answers other than 2xx/3xx ("Non-2xx or 3xx responses").
