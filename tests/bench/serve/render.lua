-- wrk script for POST /api/render (tests/bench/serve_bench.sh). FORMAT (jpeg|png), WIDTH,
-- HEIGHT come from the environment. Each answer's Server-Timing header gives the frame's own
-- render parts (select, upload, draw, readback, encode); the rest of the latency wrk measures is
-- the server's overhead (HTTP, JSON, queueing, copying) plus the network of the loopback.
local format = os.getenv("FORMAT") or "jpeg"
local width = os.getenv("WIDTH") or "640"
local height = os.getenv("HEIGHT") or "480"
local scene = os.getenv("SCENE") or "city"

wrk.method = "POST"
wrk.path = "/api/render"
wrk.headers["Content-Type"] = "application/json"
wrk.body = string.format(
  '{"scene":"%s","width":%s,"height":%s,"format":"%s","quality":85,"mode":"settled",' ..
  '"camera":{"position":[120,-60,40],"target":[120,60,5]}}', scene, width, height, format)

local threads = {}
function setup(thread)
  table.insert(threads, thread)
end

function init(args)
  renders = ""   -- per-request render parts in ms, comma-separated (a string crosses threads)
  queues = ""    -- per-request wait for a render worker, the same way
  errors = 0
end

function response(status, headers, body)
  if status ~= 200 then
    errors = errors + 1
    return
  end
  local t = headers["Server-Timing"] or headers["server-timing"]
  if not t then return end
  local sum = 0
  for name, dur in string.gmatch(t, "(%a+);dur=([%d%.]+)") do
    if name == "queue" then queues = queues .. dur .. "," end
    if name == "select" or name == "upload" or name == "draw" or name == "readback" or
       name == "encode" then
      sum = sum + tonumber(dur)
    end
  end
  renders = renders .. string.format("%.3f,", sum)
end

function done(summary, latency, requests)
  local all, waits, errs = {}, {}, 0
  for _, thread in ipairs(threads) do
    for v in string.gmatch(thread:get("renders") or "", "([^,]+)") do
      table.insert(all, tonumber(v))
    end
    for v in string.gmatch(thread:get("queues") or "", "([^,]+)") do
      table.insert(waits, tonumber(v))
    end
    errs = errs + (thread:get("errors") or 0)
  end
  table.sort(all)
  table.sort(waits)
  local function pct(list, q)
    if #list == 0 then return 0 end
    return list[math.max(1, math.ceil(q * #list))]
  end
  local p50 = latency:percentile(50) / 1000
  local p99 = latency:percentile(99) / 1000
  local rps = summary.requests / (summary.duration / 1e6)
  local render50 = pct(all, 0.5)
  io.write(string.format(
    "RESULT format=%s requests=%d errors=%d rps=%.1f p50_ms=%.2f p99_ms=%.2f " ..
    "render_p50_ms=%.2f queue_p50_ms=%.2f overhead_p50_ms=%.2f\n",
    format, summary.requests, errs + summary.errors.status, rps, p50, p99, render50,
    pct(waits, 0.5), p50 - render50))
end
