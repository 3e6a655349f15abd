local a = {}
local t = 0
for r = 1, 10 do
local s = r
for i = 0, 499 do s = (s * 1103 + 12345) % 65536; a[i] = s end
for i = 0, 498 do
  for j = 0, 498 - i do
    if a[j] > a[j + 1] then
      local x = a[j]; a[j] = a[j + 1]; a[j + 1] = x
    end
  end
end
t = t + a[250]
end
print(t)
