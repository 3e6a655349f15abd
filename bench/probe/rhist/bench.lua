local h = {}
for i = 0, 15 do h[i] = 0 end
local x = 1
for i = 1, 2000000 do
  x = (x * 1103 + 12345) % 65536
  local k = (x // 16) & 15
  h[k] = h[k] + 1
end
local s = 0
for i = 0, 15 do s = s + h[i] * (i + 1) end
print(s)
