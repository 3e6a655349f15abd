local s, c = 0, 0
local x, y
local function sub()
  y = 0
  for k = 1, 4 do y = y + (x * k) % 37 end
  s = (s + y) % 1000003
end
for i = 1, 300000 do
  x = i
  sub()
  if y > 50 then c = c + 1 end
end
print(s, c)
