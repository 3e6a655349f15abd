-- Strings: the algorithm of bench.mb in Lua 5.4.
local n = 300000
local l, t, k, h = 0, 0, 0, 0
for i = 1, n do
  local c = string.char(65 + i % 26) .. "-" .. tostring(1000 + i % 9000) .. "/" .. string.sub("XYZW", 1, 1 + i % 4)
  l = l + #c
  local p = string.find(c, "/", 1, true)
  t = t + tonumber(string.sub(c, 3, p - 1))
  if string.find(c, "7", 1, true) then k = k + 1 end
  h = (h * 31 + string.byte(c, -1)) % 1000003
end
print(string.format("L=%d T=%d K=%d H=%d", l, t, k, h))
