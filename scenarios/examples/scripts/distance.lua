-- The built-in "distance" term, written as a script (docs/extending.md): how far a body moved along one axis from
-- the start of the run to its end, m. Gives the built-in's value to the last bit.
--   params.body   the agent's body ("Middle/UpperBody")
--   params.axis   "x", "y" or "z" (+z is forward, +y up)
local body = orcs.body(params.body or "Middle/UpperBody")
local axis = ({x = 1, y = 2, z = 3})[params.axis or "z"]
if axis == nil then error("params.axis: expected \"x\", \"y\" or \"z\", found " .. tostring(params.axis)) end

local first, last

function start()
  first = select(axis, orcs.position(body))
  last = first
end

function step(dt)
  last = select(axis, orcs.position(body))
end

function finish()
  return last - first
end
